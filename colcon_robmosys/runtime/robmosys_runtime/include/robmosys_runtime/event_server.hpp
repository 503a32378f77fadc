// Copyright 2026 The colcon-robmosys authors
// Licensed under the Apache License, Version 2.0

/// \file The server of an event port, over a ROS 2 action.

#ifndef ROBMOSYS_RUNTIME__EVENT_SERVER_HPP_
#define ROBMOSYS_RUNTIME__EVENT_SERVER_HPP_

#include <algorithm>
#include <chrono>
#include <functional>
#include <future>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "rclcpp/rclcpp.hpp"
#include "rclcpp_action/rclcpp_action.hpp"

#include "robmosys_runtime/message_copy.hpp"

namespace robmosys_runtime
{

/// A provided event port: an action server whose goals are activations.
/**
 * Each accepted goal is kept, without a thread, until its client cancels it
 * or, for a single activation, until its first event. fire() publishes an
 * event as feedback of each activation whose condition holds.
 */
template<typename ActionT>
class EventServer
{
public:
  using Goal = typename ActionT::Goal;
  using Event = typename ActionT::Feedback;
  using GoalHandle = rclcpp_action::ServerGoalHandle<ActionT>;
  using Condition = std::function<bool (const Goal &, const Event &)>;

  /// Serve the event port name of a node (an rclcpp::Node or a LifecycleNode).
  /**
   * \param is_active whether activations are accepted now (nullptr: always)
   * \param condition whether an event is notified to an activation (nullptr:
   *   every event to every activation)
   * \param group the callback group of the action server (nullptr: the node's default)
   */
  template<typename NodeT>
  EventServer(
    NodeT * node, const std::string & name, const rclcpp::QoS & qos,
    std::function<bool()> is_active = nullptr, Condition condition = nullptr,
    rclcpp::CallbackGroup::SharedPtr group = nullptr)
  : state_(std::make_shared<State>())
  {
    state_->logger = node->get_logger().get_child(name);
    state_->condition = std::move(condition);
    rcl_action_server_options_t options = rcl_action_server_get_default_options();
    options.feedback_topic_qos = qos.get_rmw_qos_profile();
    auto state = state_;
    server_ = rclcpp_action::create_server<ActionT>(
      node, name,
      [state, is_active](const rclcpp_action::GoalUUID &, std::shared_ptr<const Goal>) {
        if (is_active && !is_active()) {
          RCLCPP_WARN(state->logger, "an activation was refused: the node is inactive");
          return rclcpp_action::GoalResponse::REJECT;
        }
        return rclcpp_action::GoalResponse::ACCEPT_AND_EXECUTE;
      },
      [state](const std::shared_ptr<GoalHandle> goal_handle) {
        std::lock_guard<std::mutex> lock(state->mutex);
        auto kept = state->activations.find(goal_handle->get_goal_id());
        if (kept == state->activations.end()) {
          return rclcpp_action::CancelResponse::REJECT;
        }
        state->activations.erase(kept);
        state->cancels.erase(
          std::remove_if(
            state->cancels.begin(), state->cancels.end(), [](const std::future<void> & done) {
              return done.wait_for(std::chrono::seconds(0)) == std::future_status::ready;
            }), state->cancels.end());
        // the server marks the goal canceling once this callback returned
        state->cancels.push_back(
          std::async(
            std::launch::async, [goal_handle]() {
              const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(1);
              while (!goal_handle->is_canceling() && std::chrono::steady_clock::now() < deadline) {
                std::this_thread::sleep_for(std::chrono::milliseconds(1));
              }
              if (goal_handle->is_canceling()) {
                goal_handle->canceled(std::make_shared<typename ActionT::Result>());
              }
            }));
        return rclcpp_action::CancelResponse::ACCEPT;
      },
      [state](const std::shared_ptr<GoalHandle> goal_handle) {
        std::lock_guard<std::mutex> lock(state->mutex);
        state->activations.emplace(goal_handle->get_goal_id(), goal_handle);
      }, options, group);
  }

  /// Abort the activations still kept.
  ~EventServer()
  {
    std::map<rclcpp_action::GoalUUID, std::shared_ptr<GoalHandle>> activations;
    std::vector<std::future<void>> cancels;
    {
      std::lock_guard<std::mutex> lock(state_->mutex);
      activations.swap(state_->activations);
      cancels.swap(state_->cancels);
    }
    for (auto & activation : activations) {
      if (activation.second->is_active()) {
        activation.second->abort(std::make_shared<typename ActionT::Result>());
      }
    }
  }

  /// Notify an event to each activation whose condition holds; return how many.
  size_t fire(const Event & event)
  {
    size_t notified = 0;
    std::lock_guard<std::mutex> lock(state_->mutex);
    for (auto kept = state_->activations.begin(); kept != state_->activations.end(); ) {
      const std::shared_ptr<GoalHandle> goal_handle = kept->second;
      bool holds = true;
      if (state_->condition) {
        try {
          holds = state_->condition(*goal_handle->get_goal(), event);
        } catch (const std::exception & error) {
          RCLCPP_ERROR(state_->logger, "the condition failed: %s", error.what());
          holds = false;
        }
      }
      if (!holds) {
        ++kept;
        continue;
      }
      goal_handle->publish_feedback(std::make_shared<Event>(event));
      ++notified;
      if (is_single(*goal_handle->get_goal())) {
        kept = state_->activations.erase(kept);
        goal_handle->succeed(
          std::make_shared<typename ActionT::Result>(
            convert<Event, typename ActionT::Result>(event)));
      } else {
        ++kept;
      }
    }
    return notified;
  }

  /// Return the rclcpp_action server, for what this class does not offer.
  typename rclcpp_action::Server<ActionT>::SharedPtr server() const
  {
    return server_;
  }

private:
  /// What the server's callbacks share with this port, which may go first.
  struct State
  {
    std::mutex mutex;
    rclcpp::Logger logger = rclcpp::get_logger("event");
    Condition condition;
    std::map<rclcpp_action::GoalUUID, std::shared_ptr<GoalHandle>> activations;
    std::vector<std::future<void>> cancels;
  };

  std::shared_ptr<State> state_;
  typename rclcpp_action::Server<ActionT>::SharedPtr server_;
};

}  // namespace robmosys_runtime

#endif  // ROBMOSYS_RUNTIME__EVENT_SERVER_HPP_
