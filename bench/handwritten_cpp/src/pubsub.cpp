// Copyright 2026 The colcon-robmosys authors
// Licensed under the Apache License, Version 2.0
//
// A hand-written rclcpp_lifecycle publisher/subscriber pair: the C++ reference of
// bench_runtime.py. It does what the generated C++ pair does (bench_runtime.py's models
// with language: cpp and bench/generated_cpp/), the way one would write it by hand: the
// same message type (std_msgs/msg/Header), QoS, period, callback groups and executor
// (MultiThreadedExecutor, as many threads), entities created on configure, the timer
// started on activate; the same code in the timer and the subscription; the same report.
//
//   pubsub talker|listener --ros-args -p burst:=100 ...

#include <algorithm>
#include <iostream>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "rclcpp/rclcpp.hpp"
#include "rclcpp_lifecycle/lifecycle_node.hpp"

#include "pubsub_nodes.hpp"

/// Spin the talker or the listener until SIGINT or SIGTERM.
int main(int argc, char * argv[])
{
  const std::vector<std::string> args = rclcpp::init_and_remove_ros_arguments(argc, argv);
  if (args.size() != 2 || (args[1] != "talker" && args[1] != "listener")) {
    std::cerr << "usage: pubsub talker|listener [--ros-args ...]" << std::endl;
    rclcpp::shutdown();
    return 2;
  }
  std::shared_ptr<rclcpp_lifecycle::LifecycleNode> node;
  if (args[1] == "talker") {
    node = std::make_shared<bench_handwritten::Talker>();
  } else {
    node = std::make_shared<bench_handwritten::Listener>();
  }
  // as many threads as the executor of the generated main
  const size_t threads = std::max<size_t>(std::thread::hardware_concurrency(), 2);
  rclcpp::executors::MultiThreadedExecutor executor(rclcpp::ExecutorOptions(), threads);
  executor.add_node(node->get_node_base_interface());
  executor.spin();
  executor.remove_node(node->get_node_base_interface());
  rclcpp::shutdown();
  return 0;
}
