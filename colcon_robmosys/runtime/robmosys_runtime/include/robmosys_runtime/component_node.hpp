// Copyright 2026 The colcon-robmosys authors
// Licensed under the Apache License, Version 2.0

/// \file The lifecycle bookkeeping of a component: what a generated node does not state.

#ifndef ROBMOSYS_RUNTIME__COMPONENT_NODE_HPP_
#define ROBMOSYS_RUNTIME__COMPONENT_NODE_HPP_

#include <algorithm>
#include <atomic>
#include <chrono>
#include <exception>
#include <functional>
#include <future>
#include <map>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "rclcpp/rclcpp.hpp"
#include "rclcpp_lifecycle/lifecycle_node.hpp"
#include "rclcpp_lifecycle/managed_entity.hpp"
#include "robmosys_runtime/sends.hpp"

// declared only: action_server.hpp, which a component with an action server
// includes, defines ComponentNode::create_action_server with rclcpp_action's
// headers, so that every other component compiles without them
namespace rclcpp_action
{
template<typename ActionT>
class Server;
template<typename ActionT>
class ServerGoalHandle;
}  // namespace rclcpp_action

namespace robmosys_runtime
{

namespace detail
{

/// T, in a context where no template argument is deduced (std::type_identity of C++20).
template<typename T>
struct identity
{
  using type = T;
};

}  // namespace detail

/// A lifecycle node whose ports and timers live from configure to cleanup.
/**
 * A subclass creates its ports and timers in create_ports() (called on
 * configure) and hands each port to keep(), which resets it on cleanup,
 * shutdown and error handling. Activities run only while the node is active,
 * each in a mutually exclusive callback group of its own; a function that
 * throws fails the transition it runs in, or is logged if it runs in an
 * activity, and never stops the node. A subclass that keeps ports calls
 * release() in its destructor, while its ports still exist.
 */
class ComponentNode : public rclcpp_lifecycle::LifecycleNode
{
public:
  using CallbackReturn =
    rclcpp_lifecycle::node_interfaces::LifecycleNodeInterface::CallbackReturn;

  ComponentNode(const std::string & node_name, const rclcpp::NodeOptions & options)
  : rclcpp_lifecycle::LifecycleNode(node_name, options)
  {
  }

  ~ComponentNode() override
  {
    release();
  }

  /// Return whether the node is active (activities run only then).
  bool is_active() const
  {
    return active_.load();
  }

protected:
  /// Create the ports and the timers (on configure); subclasses override it.
  virtual void create_ports() {}

  /// Add an activity: a mutually exclusive callback group of its own.
  rclcpp::CallbackGroup::SharedPtr add_activity(const std::string & name)
  {
    auto group = create_callback_group(rclcpp::CallbackGroupType::MutuallyExclusive);
    activities_[name] = group;
    return group;
  }

  /// Return the callback group of an activity.
  rclcpp::CallbackGroup::SharedPtr activity(const std::string & name) const
  {
    return activities_.at(name);
  }

  /// Return the callback group of a port's own (created once), for clients that block.
  /**
   * A blocking call from an activity waits for its answer, delivered in the
   * client's own group by another thread of the multi-threaded executor.
   */
  rclcpp::CallbackGroup::SharedPtr own_group(const std::string & port)
  {
    auto & group = own_groups_[port];
    if (!group) {
      group = create_callback_group(rclcpp::CallbackGroupType::MutuallyExclusive);
    }
    return group;
  }

  /// Declare which component this node is, and the ROS name each port is on.
  /**
   * Read-only parameters, what `colcon robmosys-import graph` recognises a
   * generated node by (the graph shows final names only); robmosys_runtime's
   * announce.py declares the same in Python. A parameter file does not
   * change them.
   */
  void announce(const std::string & package, const std::vector<std::string> & ports)
  {
    rcl_interfaces::msg::ParameterDescriptor descriptor;
    descriptor.read_only = true;
    descriptor.description = "The component package this node was generated from.";
    declare_parameter("robmosys.component", rclcpp::ParameterValue(package), descriptor, true);
    if (ports.empty()) {
      return;
    }
    std::vector<std::string> names;
    for (const auto & port : ports) {
      // the launch files remap every kind of port with plain from:=to rules
      names.push_back(port + "=" + get_node_topics_interface()->resolve_topic_name(port));
    }
    descriptor.description = "The ROS name each port of this node is on.";
    declare_parameter("robmosys.ports", rclcpp::ParameterValue(names), descriptor, true);
  }

  /// Name a parameter declared without a value: the node does not configure without one.
  void require_parameter(const std::string & name)
  {
    required_.push_back(name);
  }

  /// Set the functions a transition ("on_configure", "on_activate", ...) runs.
  void set_lifecycle(const std::string & transition, std::function<void()> functions)
  {
    lifecycle_[transition] = std::move(functions);
  }

  /// Assign a port, and reset it on release.
  template<typename T>
  std::shared_ptr<T> & keep(std::shared_ptr<T> & port, std::shared_ptr<T> created)
  {
    port = std::move(created);
    releasers_.push_back([&port]() {port.reset();});
    return port;
  }

  /// The QoS policies of a port that an operator may override at launch time.
  /**
   * ROS 2's own read-only parameters qos_overrides.<topic>.<publisher|subscription>.<policy>,
   * declared when the port is created (on configure; again after a cleanup, which finds
   * them declared and keeps their values). avoid_ros_namespace_conventions is left out:
   * it would change the name a system remaps.
   */
  static rclcpp::QosOverridingOptions qos_overriding_options()
  {
    using rclcpp::QosPolicyKind;
    return rclcpp::QosOverridingOptions(
      {QosPolicyKind::History, QosPolicyKind::Depth, QosPolicyKind::Reliability,
        QosPolicyKind::Durability, QosPolicyKind::Deadline, QosPolicyKind::Lifespan,
        QosPolicyKind::Liveliness, QosPolicyKind::LivelinessLeaseDuration});
  }

  /// Return the options of a publisher port: its QoS may be overridden.
  static rclcpp::PublisherOptions publisher_options()
  {
    rclcpp::PublisherOptions options;
    options.qos_overriding_options = qos_overriding_options();
    return options;
  }

  /// Return the options of a subscription port: its QoS may be overridden.
  static rclcpp::SubscriptionOptions subscription_options()
  {
    rclcpp::SubscriptionOptions options;
    options.qos_overriding_options = qos_overriding_options();
    return options;
  }

  /// Create the lifecycle publisher of a port: it keeps the time of its last send.
  template<typename MessageT>
  typename CountedPublisher<MessageT>::SharedPtr create_counted_publisher(
    const std::string & topic, const rclcpp::QoS & qos, const rclcpp::PublisherOptions & options)
  {
    return rclcpp::create_publisher<MessageT, std::allocator<void>, CountedPublisher<MessageT>>(
      *this, topic, qos, options);
  }

  /// Assign a lifecycle publisher: it publishes while the node is active.
  template<typename T>
  std::shared_ptr<T> & keep_publisher(std::shared_ptr<T> & port, std::shared_ptr<T> created)
  {
    publishers_.push_back(created);
    return keep(port, std::move(created));
  }

  /// Return a callback that runs functions in an activity, with what it receives.
  /**
   * The functions run only while the node is active; an exception is logged
   * and the node goes on.
   */
  template<typename ... Args>
  std::function<void(Args...)> in_activity(
    const std::string & activity,
    typename detail::identity<std::function<void(Args...)>>::type functions)
  {
    return [this, activity, functions](Args... received) {
             if (!is_active()) {
               return;
             }
             try {
               functions(received ...);
             } catch (const std::exception & error) {
               activity_failed(activity, error.what());
             }
           };
  }

  /// Create the timer of a periodic activity: started on activate, cancelled on deactivate.
  rclcpp::TimerBase::SharedPtr add_periodic(
    const std::string & activity, std::chrono::nanoseconds period,
    std::function<void()> functions)
  {
    auto run = in_activity<>(activity, std::move(functions));
    auto timer = create_wall_timer(period, [run]() {run();}, activities_.at(activity));
    timer->cancel();
    timers_.push_back(timer);
    return timer;
  }

  /// Create a service whose requests a function of an activity answers.
  /**
   * While the node is inactive, requests get the default response; an
   * exception of the function is logged, and the response goes as it is.
   */
  template<typename ServiceT>
  typename rclcpp::Service<ServiceT>::SharedPtr create_query_server(
    const std::string & name, const std::string & activity,
    std::function<void(const typename ServiceT::Request &, typename ServiceT::Response &)> answer)
  {
    return create_service<ServiceT>(
      name, [this, name, activity, answer](
        const std::shared_ptr<typename ServiceT::Request> request,
        std::shared_ptr<typename ServiceT::Response> response) {
        if (!is_active()) {
          RCLCPP_WARN(
            get_logger(), "query on the port %s while inactive: "
            "answering with the default response", name.c_str());
          return;
        }
        try {
          answer(*request, *response);
        } catch (const std::exception & error) {
          activity_failed(activity, error.what());
        }
      }, rclcpp::ServicesQoS(), activities_.at(activity));
  }

  /// Create an action server whose goals a function of an activity executes.
  /**
   * Each goal runs in a thread of its own (executing may take long, the
   * server keeps answering), one goal of the port at a time; goals are
   * accepted while the node is active, and waited for on release. Defined in
   * robmosys_runtime/action_server.hpp.
   */
  template<typename ActionT>
  std::shared_ptr<rclcpp_action::Server<ActionT>> create_action_server(
    const std::string & name, const std::string & activity,
    std::function<typename ActionT::Result(
      const std::shared_ptr<rclcpp_action::ServerGoalHandle<ActionT>>)> execute);

  CallbackReturn on_configure(const rclcpp_lifecycle::State &) override
  {
    if (!required_set()) {
      return CallbackReturn::FAILURE;
    }
    try {
      create_ports();
      run_lifecycle("on_configure");
    } catch (const std::exception & error) {
      RCLCPP_ERROR(get_logger(), "configure failed: %s", error.what());
      release();
      return CallbackReturn::FAILURE;
    } catch (...) {
      RCLCPP_ERROR(get_logger(), "configure failed: unknown exception");
      release();
      return CallbackReturn::FAILURE;
    }
    return CallbackReturn::SUCCESS;
  }

  CallbackReturn on_activate(const rclcpp_lifecycle::State &) override
  {
    return transition(
      "activate", [this]() {
        run_lifecycle("on_activate");
        for (const auto & publisher : publishers_) {
          publisher->on_activate();
        }
        active_.store(true);
        for (const auto & timer : timers_) {
          timer->reset();
        }
      });
  }

  CallbackReturn on_deactivate(const rclcpp_lifecycle::State &) override
  {
    active_.store(false);
    return transition(
      "deactivate", [this]() {
        for (const auto & timer : timers_) {
          timer->cancel();
        }
        for (const auto & publisher : publishers_) {
          publisher->on_deactivate();
        }
        run_lifecycle("on_deactivate");
      });
  }

  CallbackReturn on_cleanup(const rclcpp_lifecycle::State &) override
  {
    return end("on_cleanup", "cleanup");
  }

  CallbackReturn on_shutdown(const rclcpp_lifecycle::State &) override
  {
    return end("on_shutdown", "shutdown");
  }

  CallbackReturn on_error(const rclcpp_lifecycle::State &) override
  {
    return end("on_error", "error handling");
  }

  /// Destroy the ports and timers created on configure, after the goals being executed.
  void release()
  {
    for (const auto & timer : timers_) {
      timer->cancel();
    }
    timers_.clear();
    // the functions executing goals can check is_active()
    std::vector<std::future<void>> goals;
    {
      std::lock_guard<std::mutex> lock(goals_mutex_);
      goals.swap(goals_);
    }
    for (std::future<void> & goal : goals) {
      goal.wait();
    }
    publishers_.clear();
    std::vector<std::function<void()>> releasers;
    releasers.swap(releasers_);
    for (const auto & reset : releasers) {
      reset();
    }
  }

private:
  void activity_failed(const std::string & activity, const char * what)
  {
    if (!get_node_base_interface()->get_context()->is_valid()) {
      // SIGINT or SIGTERM shut the context down under the activity: that is
      // the shutdown, not a failure of the activity
      return;
    }
    RCLCPP_ERROR(get_logger(), "activity %s failed: %s", activity.c_str(), what);
  }

  /// Tell whether every required parameter has a value; log each that has none.
  bool required_set()
  {
    bool set = true;
    for (const auto & name : required_) {
      try {
        get_parameter(name);
      } catch (const rclcpp::exceptions::ParameterUninitializedException &) {
        RCLCPP_ERROR(
          get_logger(), "configure failed: parameter '%s' has no value (it has no default: "
          "set it in a parameter file, or with -p %s:=<value>)", name.c_str(), name.c_str());
        set = false;
      }
    }
    return set;
  }

  void run_lifecycle(const std::string & transition)
  {
    auto functions = lifecycle_.find(transition);
    if (functions != lifecycle_.end() && functions->second) {
      functions->second();
    }
  }

  CallbackReturn transition(const char * verb, const std::function<void()> & body)
  {
    try {
      body();
    } catch (const std::exception & error) {
      RCLCPP_ERROR(get_logger(), "%s failed: %s", verb, error.what());
      return CallbackReturn::FAILURE;
    } catch (...) {
      RCLCPP_ERROR(get_logger(), "%s failed: unknown exception", verb);
      return CallbackReturn::FAILURE;
    }
    return CallbackReturn::SUCCESS;
  }

  CallbackReturn end(const std::string & transition_name, const char * verb)
  {
    active_.store(false);
    const CallbackReturn result = transition(
      verb, [this, &transition_name]() {run_lifecycle(transition_name);});
    release();
    return result;
  }

  std::atomic<bool> active_{false};
  std::map<std::string, rclcpp::CallbackGroup::SharedPtr> activities_;
  std::map<std::string, rclcpp::CallbackGroup::SharedPtr> own_groups_;
  std::map<std::string, std::function<void()>> lifecycle_;
  std::vector<std::string> required_;
  std::vector<rclcpp::TimerBase::SharedPtr> timers_;
  std::vector<std::shared_ptr<rclcpp_lifecycle::ManagedEntityInterface>> publishers_;
  std::vector<std::function<void()>> releasers_;
  std::mutex goals_mutex_;
  std::vector<std::future<void>> goals_;
};

}  // namespace robmosys_runtime

#endif  // ROBMOSYS_RUNTIME__COMPONENT_NODE_HPP_
