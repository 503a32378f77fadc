// Copyright 2026 The colcon-robmosys authors
// Licensed under the Apache License, Version 2.0
//
// A hand-written rclcpp_lifecycle publisher/subscriber pair: the C++ reference of
// bench_runtime.py and bench_messages.py. It does what the generated C++ pair does
// (bench_runtime.py's models with language: cpp and bench/generated_cpp/), the way one
// would write it by hand: the same message type (std_msgs/msg/Header), QoS, period,
// callback groups, entities created on configure, the timer started on activate; the
// same code in the timer and the subscription; the same report. The executor is the
// second argument: `multi-threaded` (the default: a MultiThreadedExecutor with as many
// threads as the generated main gives it), `events`
// (rclcpp::experimental::executors::EventsExecutor) or `default`
// (`rclcpp::spin(node->get_node_base_interface())`, rclcpp's SingleThreadedExecutor, as
// the ROS 2 tutorials write it).
//
//   pubsub talker|listener [EXECUTOR] --ros-args -p burst:=100 ...

#include <algorithm>
#include <iostream>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "rclcpp/experimental/executors/events_executor/events_executor.hpp"
#include "rclcpp/rclcpp.hpp"
#include "rclcpp_lifecycle/lifecycle_node.hpp"

#include "pubsub_nodes.hpp"

namespace
{

/// Spin a node on an executor until SIGINT or SIGTERM.
void spin_on(
  rclcpp::Executor & executor, const std::shared_ptr<rclcpp_lifecycle::LifecycleNode> & node)
{
  executor.add_node(node->get_node_base_interface());
  executor.spin();
  executor.remove_node(node->get_node_base_interface());
}

}  // namespace

/// Spin the talker or the listener until SIGINT or SIGTERM.
int main(int argc, char * argv[])
{
  const std::vector<std::string> args = rclcpp::init_and_remove_ros_arguments(argc, argv);
  const std::string kind = args.size() == 3 ? args[2] : "multi-threaded";
  if (args.size() < 2 || args.size() > 3 || (args[1] != "talker" && args[1] != "listener") ||
    (kind != "multi-threaded" && kind != "events" && kind != "default"))
  {
    std::cerr << "usage: pubsub talker|listener [multi-threaded|events|default] " <<
      "[--ros-args ...]" << std::endl;
    rclcpp::shutdown();
    return 2;
  }
  std::shared_ptr<rclcpp_lifecycle::LifecycleNode> node;
  if (args[1] == "talker") {
    node = std::make_shared<bench_handwritten::Talker>();
  } else {
    node = std::make_shared<bench_handwritten::Listener>();
  }
  if (kind == "default") {
    rclcpp::spin(node->get_node_base_interface());
  } else if (kind == "events") {
    rclcpp::experimental::executors::EventsExecutor executor;
    spin_on(executor, node);
  } else {
    // as many threads as the executor of the generated main
    const size_t threads = std::max<size_t>(std::thread::hardware_concurrency(), 2);
    rclcpp::executors::MultiThreadedExecutor executor(rclcpp::ExecutorOptions(), threads);
    spin_on(executor, node);
  }
  rclcpp::shutdown();
  return 0;
}
