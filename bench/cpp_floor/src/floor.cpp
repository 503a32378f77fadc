// Copyright 2026 The colcon-robmosys authors
// Licensed under the Apache License, Version 2.0
//
// The floor of bench_bringup.py for C++ systems: what the component nodes of a
// system cost to be up in one process, whatever drives them. It makes the node of
// every instance with its component's rclcpp_components factory, as the component
// container does, then configures and activates each in turn through its own
// transitions: no load service, no lifecycle service, no DDS discovery, no other
// process. Each line of INSTANCES is one instance:
//
//   PACKAGE PLUGIN NAME NAMESPACE [ROS ARGUMENT...]
//
// with `/` for the root namespace; the ROS arguments are those bringup gives the
// node (`--params-file FILE -r FROM:=TO ...`). Prints `floor: <N> of <N> active`.
//
//   floor INSTANCES

#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "lifecycle_msgs/msg/state.hpp"
#include "rclcpp/rclcpp.hpp"
#include "rclcpp_components/component_manager.hpp"
#include "rclcpp_lifecycle/lifecycle_node.hpp"

namespace
{

struct Instance
{
  std::string package;
  std::string plugin;
  std::vector<std::string> arguments;
};

std::vector<Instance> read_instances(const std::string & path)
{
  std::vector<Instance> instances;
  std::ifstream stream(path);
  std::string line;
  while (std::getline(stream, line)) {
    std::istringstream words(line);
    Instance instance;
    std::string name;
    std::string ns;
    if (!(words >> instance.package >> instance.plugin >> name >> ns)) {
      continue;
    }
    instance.arguments = {"--ros-args", "-r", "__node:=" + name};
    if (ns != "/") {
      instance.arguments.insert(instance.arguments.end(), {"-r", "__ns:=" + ns});
    }
    std::string argument;
    while (words >> argument) {
      instance.arguments.push_back(argument);
    }
    instances.push_back(instance);
  }
  return instances;
}

}  // namespace

int main(int argc, char ** argv)
{
  if (argc < 2) {
    std::cerr << "usage: floor INSTANCES" << std::endl;
    return 2;
  }
  const std::vector<Instance> instances = read_instances(argv[1]);
  rclcpp::init(argc, argv);
  int status = 0;
  {
    // its factories, as the component container finds them in the ament index
    auto executor = std::make_shared<rclcpp::executors::SingleThreadedExecutor>();
    auto manager = std::make_shared<rclcpp_components::ComponentManager>(
      executor, "bench_cpp_floor");
    std::map<std::string, std::shared_ptr<rclcpp_components::NodeFactory>> factories;
    std::vector<rclcpp_components::NodeInstanceWrapper> wrappers;
    std::vector<std::shared_ptr<rclcpp_lifecycle::LifecycleNode>> nodes;
    for (const Instance & instance : instances) {
      auto & factory = factories[instance.plugin];
      if (!factory) {
        for (const auto & resource : manager->get_component_resources(instance.package)) {
          if (resource.first == instance.plugin) {
            factory = manager->create_component_factory(resource);
          }
        }
      }
      if (!factory) {
        std::cerr << "floor: no component " << instance.plugin << " in " <<
          instance.package << std::endl;
        return 1;
      }
      wrappers.push_back(factory->create_node_instance(
          rclcpp::NodeOptions().use_global_arguments(false).arguments(instance.arguments)));
      // a generated component derives from rclcpp_lifecycle::LifecycleNode alone
      // (robmosys_runtime::ComponentNode): the instance's address is the base's
      nodes.push_back(std::static_pointer_cast<rclcpp_lifecycle::LifecycleNode>(
          wrappers.back().get_node_instance()));
    }
    std::size_t active = 0;
    for (const auto & node : nodes) {
      if (node->configure().id() == lifecycle_msgs::msg::State::PRIMARY_STATE_INACTIVE &&
        node->activate().id() == lifecycle_msgs::msg::State::PRIMARY_STATE_ACTIVE)
      {
        ++active;
      }
    }
    std::cout << "floor: " << active << " of " << nodes.size() << " active" << std::endl;
    status = active == nodes.size() ? 0 : 1;
    nodes.clear();
    wrappers.clear();
  }
  rclcpp::shutdown();
  return status;
}
