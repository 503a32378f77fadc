// Copyright 2026 The colcon-robmosys authors
// Licensed under the Apache License, Version 2.0

/// \file The client of a query port: blocking and asynchronous calls.

#ifndef ROBMOSYS_RUNTIME__QUERY_CLIENT_HPP_
#define ROBMOSYS_RUNTIME__QUERY_CLIENT_HPP_

#include <chrono>
#include <functional>
#include <future>
#include <memory>
#include <stdexcept>
#include <string>
#include <utility>

#include "rclcpp/rclcpp.hpp"

namespace robmosys_runtime
{

/// A required query port: a service client in a callback group of its own.
/**
 * call() blocks until the answer arrives, which is safe from an activity on the
 * multi-threaded executor of the generated main: the answer is delivered in the
 * client's own group, by another thread. call_async() returns at once; the
 * answer runs the activity the port triggers.
 */
template<typename ServiceT>
class QueryClient
{
public:
  using Request = typename ServiceT::Request;
  using Response = typename ServiceT::Response;
  using AnswerCallback = std::function<void (const Response &)>;

  /// Wrap a client; on_answer (nullptr: nothing) runs for the answers of call_async().
  QueryClient(
    typename rclcpp::Client<ServiceT>::SharedPtr client, AnswerCallback on_answer = nullptr)
  : client_(std::move(client)), on_answer_(std::move(on_answer))
  {
  }

  /// Send a request and wait for the answer.
  /**
   * \throws std::runtime_error if no answer arrives within the timeout
   */
  std::shared_ptr<Response> call(
    const Request & request,
    std::chrono::nanoseconds timeout = std::chrono::seconds(5))
  {
    auto future = client_->async_send_request(std::make_shared<Request>(request));
    if (future.wait_for(timeout) != std::future_status::ready) {
      client_->remove_pending_request(future.request_id);
      throw std::runtime_error(
              std::string("no answer from the service ") + client_->get_service_name() +
              " within the timeout");
    }
    return future.get();
  }

  /// Send a request; its answer runs the activity triggered by the port.
  void call_async(const Request & request)
  {
    client_->async_send_request(
      std::make_shared<Request>(request),
      [callback = on_answer_](typename rclcpp::Client<ServiceT>::SharedFuture future) {
        if (callback) {
          callback(*future.get());
        }
      });
  }

  /// Wait until a server answers on the port, at most timeout.
  bool wait_for_service(std::chrono::nanoseconds timeout)
  {
    return client_->wait_for_service(timeout);
  }

  /// Return the rclcpp client, for what this class does not offer.
  typename rclcpp::Client<ServiceT>::SharedPtr client() const
  {
    return client_;
  }

private:
  typename rclcpp::Client<ServiceT>::SharedPtr client_;
  AnswerCallback on_answer_;
};

}  // namespace robmosys_runtime

#endif  // ROBMOSYS_RUNTIME__QUERY_CLIENT_HPP_
