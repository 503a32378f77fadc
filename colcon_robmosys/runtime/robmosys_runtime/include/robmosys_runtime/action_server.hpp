// Copyright 2026 The colcon-robmosys authors
// Licensed under the Apache License, Version 2.0

/// \file The server of an action port: ComponentNode::create_action_server.

#ifndef ROBMOSYS_RUNTIME__ACTION_SERVER_HPP_
#define ROBMOSYS_RUNTIME__ACTION_SERVER_HPP_

#include <algorithm>
#include <chrono>
#include <exception>
#include <functional>
#include <future>
#include <memory>
#include <mutex>
#include <string>

#include "rclcpp_action/rclcpp_action.hpp"
#include "robmosys_runtime/component_node.hpp"

namespace robmosys_runtime
{

template<typename ActionT>
std::shared_ptr<rclcpp_action::Server<ActionT>> ComponentNode::create_action_server(
  const std::string & name, const std::string & activity,
  std::function<typename ActionT::Result(
    const std::shared_ptr<rclcpp_action::ServerGoalHandle<ActionT>>)> execute)
{
  using GoalHandle = rclcpp_action::ServerGoalHandle<ActionT>;
  auto serial = std::make_shared<std::mutex>();
  auto run = [this, activity, execute, serial](const std::shared_ptr<GoalHandle> goal_handle) {
      std::lock_guard<std::mutex> lock(*serial);
      auto result = std::make_shared<typename ActionT::Result>();
      try {
        *result = execute(goal_handle);
      } catch (const std::exception & error) {
        activity_failed(activity, error.what());
        goal_handle->abort(result);
        return;
      }
      if (goal_handle->is_canceling()) {
        goal_handle->canceled(result);
      } else {
        goal_handle->succeed(result);
      }
    };
  return rclcpp_action::create_server<ActionT>(
    this, name,
    [this, name](const rclcpp_action::GoalUUID &, std::shared_ptr<const typename ActionT::Goal>) {
      if (!is_active()) {
        RCLCPP_WARN(get_logger(), "goal on the port %s rejected: the node is inactive",
        name.c_str());
        return rclcpp_action::GoalResponse::REJECT;
      }
      return rclcpp_action::GoalResponse::ACCEPT_AND_EXECUTE;
    },
    [](const std::shared_ptr<GoalHandle>) {
      return rclcpp_action::CancelResponse::ACCEPT;
    },
    [this, run](const std::shared_ptr<GoalHandle> goal_handle) {
      std::lock_guard<std::mutex> lock(goals_mutex_);
      goals_.erase(
        std::remove_if(
          goals_.begin(), goals_.end(), [](const std::future<void> & goal) {
            return goal.wait_for(std::chrono::seconds(0)) == std::future_status::ready;
          }), goals_.end());
      goals_.push_back(std::async(std::launch::async, run, goal_handle));
    }, rcl_action_server_get_default_options(), activities_.at(activity));
}

}  // namespace robmosys_runtime

#endif  // ROBMOSYS_RUNTIME__ACTION_SERVER_HPP_
