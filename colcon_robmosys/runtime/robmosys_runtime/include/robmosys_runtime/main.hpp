// Copyright 2026 The colcon-robmosys authors
// Licensed under the Apache License, Version 2.0

/// \file The process of a component: one lifecycle node on the executor of its model.

#ifndef ROBMOSYS_RUNTIME__MAIN_HPP_
#define ROBMOSYS_RUNTIME__MAIN_HPP_

#include <algorithm>
#include <exception>
#include <memory>
#include <thread>

#include "lifecycle_msgs/msg/state.hpp"
#include "rclcpp/experimental/executors/events_executor/events_executor.hpp"
#include "rclcpp/rclcpp.hpp"

namespace robmosys_runtime
{

/// The executors a model names (docs/model-format.md, "Executors").
enum class Executor
{
  /// rclcpp::experimental::executors::EventsExecutor: one thread, no wait set per callback
  EVENTS,
  /// rclcpp::executors::SingleThreadedExecutor
  SINGLE_THREADED,
  /// rclcpp::executors::MultiThreadedExecutor, a thread per callback group and one more
  MULTI_THREADED,
};

/// Return an executor of a kind; a multi-threaded one has at least min_threads threads.
inline std::shared_ptr<rclcpp::Executor> make_executor(Executor kind, size_t min_threads)
{
  switch (kind) {
    case Executor::EVENTS:
      return std::make_shared<rclcpp::experimental::executors::EventsExecutor>();
    case Executor::SINGLE_THREADED:
      return std::make_shared<rclcpp::executors::SingleThreadedExecutor>();
    default:
      return std::make_shared<rclcpp::executors::MultiThreadedExecutor>(
        rclcpp::ExecutorOptions(),
        std::max<size_t>(std::thread::hardware_concurrency(), min_threads));
  }
}

/// Spin a NodeT (a LifecycleNode) on an executor until SIGINT or SIGTERM.
/**
 * Before the context shuts down, the node takes its shutdown transition (its
 * on_shutdown functions run, ports are released) while it can still tell the
 * lifecycle clients. A multi-threaded executor has at least min_threads threads,
 * so that a blocking call in one activity never starves the thread that delivers
 * its answer.
 * \return the exit status of the process
 */
template<typename NodeT>
int run(
  int argc, char * argv[], size_t min_threads, const char * logger_name,
  Executor kind = Executor::MULTI_THREADED)
{
  // rclcpp::init installs the SIGINT and SIGTERM handlers that end spin()
  rclcpp::init(argc, argv);
  int status = 0;
  try {
    auto node = std::make_shared<NodeT>();
    std::weak_ptr<NodeT> weak_node = node;
    rclcpp::contexts::get_global_default_context()->add_pre_shutdown_callback(
      [weak_node]() {
        auto alive = weak_node.lock();
        const auto finalized = lifecycle_msgs::msg::State::PRIMARY_STATE_FINALIZED;
        if (alive && alive->get_current_state().id() != finalized) {
          alive->shutdown();
        }
      });
    auto executor = make_executor(kind, min_threads);
    executor->add_node(node->get_node_base_interface());
    executor->spin();
    executor->remove_node(node->get_node_base_interface());
  } catch (const std::exception & error) {
    RCLCPP_FATAL(rclcpp::get_logger(logger_name), "%s", error.what());
    status = 1;
  }
  rclcpp::shutdown();
  return status;
}

}  // namespace robmosys_runtime

#endif  // ROBMOSYS_RUNTIME__MAIN_HPP_
