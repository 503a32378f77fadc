// Copyright 2026 The colcon-robmosys authors
// Licensed under the Apache License, Version 2.0

/// \file The client of an event port, over a ROS 2 action.

#ifndef ROBMOSYS_RUNTIME__EVENT_CLIENT_HPP_
#define ROBMOSYS_RUNTIME__EVENT_CLIENT_HPP_

#include <atomic>
#include <chrono>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <utility>
#include <vector>

#include "action_msgs/msg/goal_status.hpp"
#include "rclcpp/rclcpp.hpp"
#include "rclcpp_action/rclcpp_action.hpp"

#include "robmosys_runtime/message_copy.hpp"

namespace robmosys_runtime
{

/// An activation of an event by a required event port.
template<typename ActionT>
class EventActivation
{
public:
  using GoalHandle = rclcpp_action::ClientGoalHandle<ActionT>;

  /// Whether an activation is over; it reads as the bool it is (and load()).
  class Ended
  {
public:
    explicit Ended(const EventActivation & activation)
    : activation_(activation)
    {
    }

    Ended(const Ended &) = delete;
    Ended & operator=(const Ended &) = delete;

    /// Finished as the client saw it, or its goal ended by its server: the status
    /// (transient local) comes where the result may not (rmw_fastrtps drops an answer
    /// to a reader it has not matched, as under load to a server released right after
    /// it aborted the goal).
    bool load() const
    {
      if (activation_.finished) {
        return true;
      }
      return ended_by_server(activation_.goal_handle());
    }

    /// Implicit, as the std::atomic<bool> it was.
    operator bool() const
    {
      return load();
    }

private:
    const EventActivation & activation_;
  };

  explicit EventActivation(bool single_activation)
  : single(single_activation), ended(*this)
  {
  }

  /// The goal, once the server accepted the activation (nullptr until then).
  typename GoalHandle::SharedPtr goal_handle() const
  {
    std::lock_guard<std::mutex> lock(goal_mutex_);
    return goal_handle_;
  }

  /// The first event ends the activation.
  const bool single;
  /// How many events of this activation ran the activity.
  std::atomic<size_t> events{0};
  /// Deactivated, ended by its single event or by its result, or refused.
  std::atomic<bool> finished{false};
  /// Over: finished, or its goal ended by its server.
  const Ended ended;

  /// Whether the status of a goal says its server ended it (false without a goal).
  /**
   * It takes the goal handle's lock, which rclcpp_action holds while it runs the
   * callbacks of the goal: never ask it while holding a lock those callbacks take.
   */
  static bool ended_by_server(const typename GoalHandle::SharedPtr & goal)
  {
    if (!goal) {
      return false;
    }
    const auto status = goal->get_status();
    return status == action_msgs::msg::GoalStatus::STATUS_SUCCEEDED ||
           status == action_msgs::msg::GoalStatus::STATUS_CANCELED ||
           status == action_msgs::msg::GoalStatus::STATUS_ABORTED;
  }

private:
  template<typename>
  friend class EventClient;

  void set_goal_handle(typename GoalHandle::SharedPtr goal)
  {
    std::lock_guard<std::mutex> lock(goal_mutex_);
    goal_handle_ = std::move(goal);
  }

  mutable std::mutex goal_mutex_;
  typename GoalHandle::SharedPtr goal_handle_;
};

/// A required event port: an action client whose goals are activations.
/**
 * Each event of an activation runs the activity the port triggers; deactivating
 * cancels the goal. An activation made before the server is there (a client
 * activated before discovery found the server) waits, and is sent once the
 * server has been seen for half a second: a goal sent to no server is lost, and
 * so would be every event of it.
 */
template<typename ActionT>
class EventClient
{
public:
  using Goal = typename ActionT::Goal;
  using Event = typename ActionT::Feedback;
  using Activation = EventActivation<ActionT>;
  using GoalHandle = rclcpp_action::ClientGoalHandle<ActionT>;
  using EventCallback = std::function<void (const Event &)>;

  /// Use the event port name of a node (an rclcpp::Node or a LifecycleNode).
  /**
   * \param on_event what each event of an activation runs (nullptr: nothing)
   * \param group the callback group of the action client (nullptr: the node's default)
   */
  template<typename NodeT>
  EventClient(
    NodeT * node, const std::string & name, const rclcpp::QoS & qos,
    EventCallback on_event = nullptr, rclcpp::CallbackGroup::SharedPtr group = nullptr)
  : state_(std::make_shared<State>())
  {
    state_->logger = node->get_logger().get_child(name);
    state_->on_event = std::move(on_event);
    rcl_action_client_options_t options = rcl_action_client_get_default_options();
    options.feedback_topic_qos = qos.get_rmw_qos_profile();
    state_->client = rclcpp_action::create_client<ActionT>(node, name, group, options);
    // the timer that sends waiting activations is the node's, dropped with the port
    state_->make_timer = [node, group](std::function<void()> callback) {
        return node->create_wall_timer(kWaitPeriod, std::move(callback), group);
      };
  }

  /// Deactivate every activation.
  ~EventClient()
  {
    std::vector<std::shared_ptr<Activation>> activations;
    rclcpp::TimerBase::SharedPtr timer;
    {
      std::lock_guard<std::mutex> lock(state_->mutex);
      activations = state_->activations;
      timer = std::move(state_->waiting_timer);
      state_->waiting.clear();
    }
    if (timer) {
      timer->cancel();
    }
    for (const auto & activation : activations) {
      deactivate(activation);
    }
    std::lock_guard<std::mutex> lock(state_->mutex);
    for (const auto & activation : state_->activations) {
      activation->set_goal_handle(nullptr);
    }
    state_->activations.clear();
  }

  /// Wait until the event server is there, at most timeout; return whether it is.
  bool wait_for_server(std::chrono::nanoseconds timeout)
  {
    return state_->client->wait_for_action_server(timeout);
  }

  /// Activate the event; with single, its first event ends the activation.
  /**
   * \throws std::invalid_argument if single is asked of an event without the field
   */
  std::shared_ptr<Activation> activate(Goal activation, bool single = false)
  {
    set_single(activation, single);
    auto handle = std::make_shared<Activation>(single);
    {
      std::lock_guard<std::mutex> lock(state_->mutex);
      state_->activations.push_back(handle);
      if (!state_->waiting.empty() || !state_->client->action_server_is_ready()) {
        state_->waiting.emplace_back(handle, activation);
        if (!state_->waiting_timer) {
          std::weak_ptr<State> weak_state = state_;
          state_->waiting_timer = state_->make_timer(
            [weak_state]() {
              auto state = weak_state.lock();
              if (state) {
                send_waiting(state);
              }
            });
        }
        return handle;
      }
    }
    send(state_, handle, activation);
    return handle;
  }

  /// End an activation: none of its events runs the activity any more.
  void deactivate(const std::shared_ptr<Activation> & handle)
  {
    typename GoalHandle::SharedPtr goal;
    {
      std::lock_guard<std::mutex> lock(state_->mutex);
      if (!handle->finished.exchange(true)) {
        goal = handle->goal_handle();
      }
    }
    // the status is read outside the lock: rclcpp_action runs the result and feedback
    // callbacks (which take it) holding the goal handle's lock, which get_status() takes
    if (goal && !Activation::ended_by_server(goal)) {
      cancel(state_, goal);
    }
  }

  /// Return the rclcpp_action client, for what this class does not offer.
  typename rclcpp_action::Client<ActionT>::SharedPtr client() const
  {
    return state_->client;
  }

private:
  /// Time between two looks for the server, while activations wait for it.
  static constexpr std::chrono::milliseconds kWaitPeriod{100};
  /// How long the server has been seen before the activations that waited go: the
  /// client sees the server before the server has matched the client (DDS matches
  /// each direction on its own), and a goal sent in between is lost.
  static constexpr std::chrono::milliseconds kServerSettle{500};

  /// What the client's callbacks share with this port, which may go first.
  struct State
  {
    std::mutex mutex;
    rclcpp::Logger logger = rclcpp::get_logger("event");
    EventCallback on_event;
    typename rclcpp_action::Client<ActionT>::SharedPtr client;
    std::vector<std::shared_ptr<Activation>> activations;
    /// Activations made before the server was there, and the timer that sends them.
    std::vector<std::pair<std::shared_ptr<Activation>, Goal>> waiting;
    rclcpp::TimerBase::SharedPtr waiting_timer;
    std::function<rclcpp::TimerBase::SharedPtr(std::function<void()>)> make_timer;
    bool server_seen = false;
    std::chrono::steady_clock::time_point server_since;
  };

  /// Send the activations that waited, in their order, once the server is there.
  static void send_waiting(const std::shared_ptr<State> & state)
  {
    std::vector<std::pair<std::shared_ptr<Activation>, Goal>> waiting;
    {
      std::lock_guard<std::mutex> lock(state->mutex);
      if (!state->waiting_timer) {
        return;
      }
      if (!state->client->action_server_is_ready()) {
        state->server_seen = false;
        return;
      }
      const auto now = std::chrono::steady_clock::now();
      if (!state->server_seen) {
        state->server_seen = true;
        state->server_since = now;
      }
      if (now - state->server_since < kServerSettle) {
        return;
      }
      waiting.swap(state->waiting);
      // the executor holds the timer while this runs: dropping it here is safe
      state->waiting_timer->cancel();
      state->waiting_timer.reset();
      state->server_seen = false;
    }
    for (auto & [handle, activation] : waiting) {
      if (!handle->finished) {  // deactivated while it waited: nothing to send
        send(state, handle, activation);
      }
    }
  }

  /// Send one activation.
  static void send(
    const std::shared_ptr<State> & state, const std::shared_ptr<Activation> & handle,
    const Goal & activation)
  {
    // the goal handle keeps these callbacks and the activation keeps the goal
    // handle: weak references break the cycle
    std::weak_ptr<State> weak_state = state;
    std::weak_ptr<Activation> weak_handle = handle;
    typename rclcpp_action::Client<ActionT>::SendGoalOptions options;
    options.goal_response_callback = [weak_state, weak_handle](
      typename GoalHandle::SharedPtr goal) {
        auto state = weak_state.lock();
        if (state) {
          accepted(state, weak_handle.lock(), goal);
        }
      };
    options.feedback_callback = [weak_state, weak_handle](
      typename GoalHandle::SharedPtr, const std::shared_ptr<const Event> event) {
        auto state = weak_state.lock();
        auto handle = weak_handle.lock();
        if (state && handle) {
          notify(state, handle, *event, false);
        }
      };
    options.result_callback = [weak_state, weak_handle](
      const typename GoalHandle::WrappedResult & result) {
        auto state = weak_state.lock();
        auto handle = weak_handle.lock();
        if (!state || !handle) {
          return;
        }
        if (handle->single && result.code == rclcpp_action::ResultCode::SUCCEEDED &&
          result.result)
        {
          // the event that ended a single activation is its result too, if its feedback was lost
          notify(state, handle, convert<typename ActionT::Result, Event>(*result.result), true);
        }
        handle->finished = true;
      };
    state->client->async_send_goal(activation, options);
  }

  /// Cancel a goal; one that ended meanwhile (its result came) is not cancelled.
  static void cancel(const std::shared_ptr<State> & state, typename GoalHandle::SharedPtr goal)
  {
    try {
      state->client->async_cancel_goal(goal);
    } catch (const rclcpp_action::exceptions::UnknownGoalHandleError &) {
    }
  }

  static void accepted(
    const std::shared_ptr<State> & state, const std::shared_ptr<Activation> & handle,
    typename GoalHandle::SharedPtr goal)
  {
    if (!goal) {
      RCLCPP_WARN(state->logger, "an activation was refused");
      if (handle) {
        handle->finished = true;
      }
      return;
    }
    if (!handle) {
      // nobody holds the activation any more: it ends
      cancel(state, goal);
      return;
    }
    bool finished;
    {
      std::lock_guard<std::mutex> lock(state->mutex);
      handle->set_goal_handle(goal);
      finished = handle->finished;
    }
    if (finished) {
      cancel(state, goal);
    }
  }

  static void notify(
    const std::shared_ptr<State> & state, const std::shared_ptr<Activation> & handle,
    const Event & event, bool from_result)
  {
    {
      std::lock_guard<std::mutex> lock(state->mutex);
      if (handle->finished) {
        return;
      }
      ++handle->events;
      handle->finished = handle->single || from_result;
    }
    if (state->on_event) {
      state->on_event(event);
    }
  }

  std::shared_ptr<State> state_;
};

}  // namespace robmosys_runtime

#endif  // ROBMOSYS_RUNTIME__EVENT_CLIENT_HPP_
