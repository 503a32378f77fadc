// Copyright 2026 The colcon-robmosys authors
// Licensed under the Apache License, Version 2.0

/// \file The process of a component: one lifecycle node on a multi-threaded executor.

#ifndef ROBMOSYS_RUNTIME__MAIN_HPP_
#define ROBMOSYS_RUNTIME__MAIN_HPP_

#include <algorithm>
#include <exception>
#include <memory>
#include <thread>

#include "lifecycle_msgs/msg/state.hpp"
#include "rclcpp/rclcpp.hpp"

namespace robmosys_runtime
{

/// Spin a NodeT (a LifecycleNode) on a multi-threaded executor until SIGINT or SIGTERM.
/**
 * Before the context shuts down, the node takes its shutdown transition (its
 * on_shutdown functions run, ports are released) while it can still tell the
 * lifecycle clients. The executor has at least min_threads threads, so that a
 * blocking call in one activity never starves the thread that delivers its answer.
 * \return the exit status of the process
 */
template<typename NodeT>
int run(int argc, char * argv[], size_t min_threads, const char * logger_name)
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
    const size_t threads =
      std::max<size_t>(std::thread::hardware_concurrency(), min_threads);
    rclcpp::executors::MultiThreadedExecutor executor(rclcpp::ExecutorOptions(), threads);
    executor.add_node(node->get_node_base_interface());
    executor.spin();
    executor.remove_node(node->get_node_base_interface());
  } catch (const std::exception & error) {
    RCLCPP_FATAL(rclcpp::get_logger(logger_name), "%s", error.what());
    status = 1;
  }
  rclcpp::shutdown();
  return status;
}

}  // namespace robmosys_runtime

#endif  // ROBMOSYS_RUNTIME__MAIN_HPP_
