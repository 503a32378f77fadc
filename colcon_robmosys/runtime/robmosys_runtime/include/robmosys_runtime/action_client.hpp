// Copyright 2026 The colcon-robmosys authors
// Licensed under the Apache License, Version 2.0

/// \file The client of an action port: blocking and asynchronous goals.

#ifndef ROBMOSYS_RUNTIME__ACTION_CLIENT_HPP_
#define ROBMOSYS_RUNTIME__ACTION_CLIENT_HPP_

#include <chrono>
#include <functional>
#include <future>
#include <memory>
#include <stdexcept>
#include <string>
#include <utility>

#include "rclcpp/rclcpp.hpp"
#include "rclcpp_action/rclcpp_action.hpp"

namespace robmosys_runtime
{

/// A required action port: an action client in a callback group of its own.
/**
 * send_goal_async() returns at once; the result runs the activity the port
 * triggers. send_goal() blocks until the result arrives, which is safe from an
 * activity on the multi-threaded executor of the generated main.
 */
template<typename ActionT>
class ActionClient
{
public:
  using Goal = typename ActionT::Goal;
  using Result = typename ActionT::Result;
  using Feedback = typename ActionT::Feedback;
  using GoalHandle = rclcpp_action::ClientGoalHandle<ActionT>;
  using WrappedResult = typename GoalHandle::WrappedResult;
  using FeedbackCallback = std::function<void (const Feedback &)>;
  using ResultCallback = std::function<void (const Result &)>;

  /// Wrap a client; on_result (nullptr: nothing) runs for the results of send_goal_async().
  ActionClient(
    typename rclcpp_action::Client<ActionT>::SharedPtr client, std::string name,
    ResultCallback on_result = nullptr)
  : client_(std::move(client)), name_(std::move(name)), on_result_(std::move(on_result))
  {
  }

  /// Send a goal; its result runs the activity triggered by the port.
  std::shared_future<typename GoalHandle::SharedPtr> send_goal_async(
    const Goal & goal, FeedbackCallback feedback = nullptr)
  {
    auto options = feedback_options(feedback);
    options.result_callback = [callback = on_result_](const WrappedResult & result) {
        if (callback && result.result) {
          callback(*result.result);
        }
      };
    return client_->async_send_goal(goal, options);
  }

  /// Send a goal and wait for its result.
  /**
   * \throws std::runtime_error if the goal is rejected or the result does not
   *   arrive within the timeout (the goal is then cancelled)
   */
  WrappedResult send_goal(
    const Goal & goal, std::chrono::nanoseconds timeout,
    FeedbackCallback feedback = nullptr)
  {
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    auto goal_future = client_->async_send_goal(goal, feedback_options(feedback));
    if (goal_future.wait_until(deadline) != std::future_status::ready) {
      throw std::runtime_error(
              std::string("no answer from the action server ") + name_ +
              " within the timeout");
    }
    auto handle = goal_future.get();
    if (!handle) {
      throw std::runtime_error(
              std::string("the action server ") + name_ +
              " rejected the goal");
    }
    auto result_future = client_->async_get_result(handle);
    if (result_future.wait_until(deadline) != std::future_status::ready) {
      client_->async_cancel_goal(handle);
      throw std::runtime_error(
              std::string("no result from the action server ") + name_ +
              " within the timeout");
    }
    return result_future.get();
  }

  /// Wait until a server answers on the port, at most timeout.
  bool wait_for_action_server(std::chrono::nanoseconds timeout)
  {
    return client_->wait_for_action_server(timeout);
  }

  /// Return the rclcpp_action client, for what this class does not offer.
  typename rclcpp_action::Client<ActionT>::SharedPtr client() const
  {
    return client_;
  }

private:
  typename rclcpp_action::Client<ActionT>::SendGoalOptions feedback_options(
    FeedbackCallback feedback)
  {
    typename rclcpp_action::Client<ActionT>::SendGoalOptions options;
    if (feedback) {
      options.feedback_callback = [feedback](
        typename GoalHandle::SharedPtr, const std::shared_ptr<const Feedback> message) {
          feedback(*message);
        };
    }
    return options;
  }

  typename rclcpp_action::Client<ActionT>::SharedPtr client_;
  std::string name_;
  ResultCallback on_result_;
};

}  // namespace robmosys_runtime

#endif  // ROBMOSYS_RUNTIME__ACTION_CLIENT_HPP_
