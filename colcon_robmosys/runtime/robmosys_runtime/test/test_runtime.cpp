// Copyright 2026 The colcon-robmosys authors
// Licensed under the Apache License, Version 2.0

#include <stdlib.h>

#include <algorithm>
#include <atomic>
#include <cstdio>
#include <chrono>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <functional>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "action_msgs/msg/goal_status.hpp"
#include "rclcpp/rclcpp.hpp"
#include "rclcpp_action/rclcpp_action.hpp"
#include "std_msgs/msg/int32.hpp"
#include "test_msgs/action/fibonacci.hpp"
#include "test_msgs/srv/basic_types.hpp"

#include "robmosys_runtime/action_client.hpp"
#include "robmosys_runtime/action_server.hpp"
#include "robmosys_runtime/component_node.hpp"
#include "robmosys_runtime/event_client.hpp"
#include "robmosys_runtime/event_server.hpp"
#include "robmosys_runtime/main.hpp"
#include "robmosys_runtime/parameters.hpp"
#include "robmosys_runtime/query_client.hpp"
#include "robmosys_runtime/sends.hpp"

using namespace std::chrono_literals;
using Fibonacci = test_msgs::action::Fibonacci;
using BasicTypes = test_msgs::srv::BasicTypes;

namespace
{

int failures = 0;

/// Count a failed check, and tell where it is (the test goes on, like EXPECT_TRUE).
void check(bool holds, const char * what, int line)
{
  if (!holds) {
    std::fprintf(stderr, "test_runtime.cpp:%d: check failed: %s\n", line, what);
    ++failures;
  }
}

#define EXPECT(condition) check((condition), #condition, __LINE__)

bool wait_until(const std::function<bool()> & condition, std::chrono::milliseconds timeout = 10s)
{
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (std::chrono::steady_clock::now() < deadline) {
    if (condition()) {
      return true;
    }
    std::this_thread::sleep_for(20ms);
  }
  return condition();
}

/// rclcpp, and an executor spinning in a thread, for one test.
class Runtime
{
public:
  Runtime()
  {
    rclcpp::init(0, nullptr);
    executor_ = std::make_shared<rclcpp::executors::MultiThreadedExecutor>(
      rclcpp::ExecutorOptions(), 4);
  }

  ~Runtime()
  {
    stop();
    executor_.reset();
    rclcpp::shutdown();
  }

  /// Stop spinning, before the nodes and ports of a test go.
  void stop()
  {
    if (spinner_.joinable()) {
      // a cancel() before spin() has begun is lost, and spin() would never end
      wait_until([this]() {return executor_->is_spinning();}, 10s);
      executor_->cancel();
      spinner_.join();
    }
  }

  Runtime(const Runtime &) = delete;
  Runtime & operator=(const Runtime &) = delete;

  template<typename NodeT>
  void spin(const std::shared_ptr<NodeT> & node)
  {
    executor_->add_node(node->get_node_base_interface());
  }

  void start()
  {
    spinner_ = std::thread([this]() {executor_->spin();});
  }

private:
  std::shared_ptr<rclcpp::executors::MultiThreadedExecutor> executor_;
  std::thread spinner_;
};

/// The two sides of an event port, a sensor that fires and a watcher that
/// activates, each a node of its own, spun by a runtime of their own.
struct EventSides
{
  explicit EventSides(const std::string & prefix)
  : sensor(std::make_shared<rclcpp::Node>(prefix + "sensor")),
    watcher(std::make_shared<rclcpp::Node>(prefix + "watcher"))
  {
  }

  /// Spin both nodes, with the ports made so far.
  void start()
  {
    runtime.spin(sensor);
    runtime.spin(watcher);
    runtime.start();
  }

  Runtime runtime;  // first: rclcpp is initialised before the nodes are made
  std::shared_ptr<rclcpp::Node> sensor;
  std::shared_ptr<rclcpp::Node> watcher;
};

/// An activation of an event port: events of at least order hold its condition.
Fibonacci::Goal activation_of(int order)
{
  Fibonacci::Goal activation;
  activation.order = order;
  return activation;
}

/// An event whose value is first.
Fibonacci::Feedback event_of(int first)
{
  Fibonacci::Feedback event;
  event.sequence = {first};
  return event;
}

/// The condition of the events of the tests: the event's value reaches the activation's order.
bool reaches(const Fibonacci::Goal & activation, const Fibonacci::Feedback & event)
{
  return event.sequence.at(0) >= activation.order;
}

/// A component that counts periodically and publishes the count.
class Counter : public robmosys_runtime::ComponentNode
{
public:
  Counter()
  : ComponentNode("counter", rclcpp::NodeOptions())
  {
    add_activity("Tick");
    add_activity("Answer");
    set_lifecycle(
      "on_configure", [this]() {
        if (fail_configure) {
          throw std::runtime_error("the set-up fails");
        }
      });
  }

  ~Counter() override
  {
    release();
  }

  std::atomic<bool> fail_configure{false};
  std::atomic<int> count{0};
  robmosys_runtime::CountedPublisher<std_msgs::msg::Int32>::SharedPtr pCount;
  rclcpp::Service<BasicTypes>::SharedPtr qDouble;
  rclcpp::Subscription<std_msgs::msg::Int32>::SharedPtr sCount;
  std::atomic<int> received{0};

protected:
  void create_ports() override
  {
    keep_publisher(pCount, create_counted_publisher<std_msgs::msg::Int32>("pCount", 10, {}));
    rclcpp::SubscriptionOptions options;
    options.callback_group = activity("Answer");
    keep(
      sCount, create_subscription<std_msgs::msg::Int32>(
        "pCount", 10, in_activity<const std_msgs::msg::Int32 &>(
          "Answer", [this](const std_msgs::msg::Int32 & message) {received = message.data;}),
        options));
    keep(
      qDouble, create_query_server<BasicTypes>(
        "qDouble", "Answer",
        [](const BasicTypes::Request & request, BasicTypes::Response & response) {
          response.int32_value = 2 * request.int32_value;
        }));
    add_periodic(
      "Tick", 20ms, [this]() {
        std_msgs::msg::Int32 message;
        message.data = ++count;
        pCount->publish(message);
        if (count == 2) {
          throw std::runtime_error("the second tick fails");
        }
      });
  }
};

/// An action server that accepts each goal and never answers the request for its
/// result: the result of a goal its server ended, lost (rmw_fastrtps drops an answer
/// to a reader it has not matched, as under load to a server released right after
/// it aborted the goal). Its status, transient local, still tells the goal's end.
class ResultlessServer
{
public:
  using Impl = Fibonacci::Impl;

  ResultlessServer(rclcpp::Node * node, const std::string & name)
  {
    const std::string prefix = name + "/_action/";
    send_goal_ = node->create_service<Impl::SendGoalService>(
      prefix + "send_goal",
      [this](
        const std::shared_ptr<Impl::SendGoalService::Request> request,
        std::shared_ptr<Impl::SendGoalService::Response> response) {
        response->accepted = true;
        std::lock_guard<std::mutex> lock(mutex_);
        goals_.push_back(request->goal_id);
      });
    cancel_goal_ = node->create_service<Impl::CancelGoalService>(
      prefix + "cancel_goal",
      [](
        const std::shared_ptr<Impl::CancelGoalService::Request>,
        std::shared_ptr<Impl::CancelGoalService::Response> response) {
        response->return_code = Impl::CancelGoalService::Response::ERROR_REJECTED;
      });
    // deferred, and never answered
    get_result_ = node->create_service<Impl::GetResultService>(
      prefix + "get_result",
      [](std::shared_ptr<rmw_request_id_t>, std::shared_ptr<Impl::GetResultService::Request>) {});
    feedback_ = node->create_publisher<Impl::FeedbackMessage>(prefix + "feedback", 10);
    status_ = node->create_publisher<Impl::GoalStatusMessage>(
      prefix + "status", rclcpp::QoS(1).reliable().transient_local());
  }

  size_t goals()
  {
    std::lock_guard<std::mutex> lock(mutex_);
    return goals_.size();
  }

  /// Publish the end of every goal, aborted.
  void abort()
  {
    Impl::GoalStatusMessage statuses;
    std::lock_guard<std::mutex> lock(mutex_);
    for (const auto & goal : goals_) {
      action_msgs::msg::GoalStatus status;
      status.goal_info.goal_id = goal;
      status.status = action_msgs::msg::GoalStatus::STATUS_ABORTED;
      statuses.status_list.push_back(status);
    }
    status_->publish(statuses);
  }

private:
  std::mutex mutex_;
  std::vector<Impl::SendGoalService::Request::_goal_id_type> goals_;
  rclcpp::Service<Impl::SendGoalService>::SharedPtr send_goal_;
  rclcpp::Service<Impl::CancelGoalService>::SharedPtr cancel_goal_;
  rclcpp::Service<Impl::GetResultService>::SharedPtr get_result_;
  rclcpp::Publisher<Impl::FeedbackMessage>::SharedPtr feedback_;
  rclcpp::Publisher<Impl::GoalStatusMessage>::SharedPtr status_;
};

}  // namespace

void query_client()
{
  Runtime runtime;
  auto server = std::make_shared<rclcpp::Node>("server");
  auto service = server->create_service<BasicTypes>(
    "add", [](
      const std::shared_ptr<BasicTypes::Request> request,
      std::shared_ptr<BasicTypes::Response> response) {
      response->int32_value = request->int32_value + 1000;
    });
  auto client_node = std::make_shared<rclcpp::Node>("client");
  auto group = client_node->create_callback_group(rclcpp::CallbackGroupType::MutuallyExclusive);
  std::atomic<int> answered{0};
  robmosys_runtime::QueryClient<BasicTypes> query(
    client_node->create_client<BasicTypes>("add", rclcpp::ServicesQoS(), group),
    [&answered](const BasicTypes::Response & response) {answered = response.int32_value;});
  runtime.spin(server);
  runtime.spin(client_node);
  runtime.start();
  EXPECT(query.wait_for_service(10s));
  BasicTypes::Request request;
  request.int32_value = 5;
  EXPECT(query.call(request)->int32_value == 1005);
  request.int32_value = 7;
  query.call_async(request);
  EXPECT(wait_until([&answered]() {return answered == 1007;}));
  runtime.stop();
}

void events_reach_the_activations_whose_condition_holds()
{
  EventSides sides("");
  robmosys_runtime::EventServer<Fibonacci> server(
    sides.sensor.get(), "event", rclcpp::QoS(10), nullptr, reaches);
  std::atomic<int> events{0};
  robmosys_runtime::EventClient<Fibonacci> client(
    sides.watcher.get(), "event", rclcpp::QoS(10),
    [&events](const Fibonacci::Feedback &) {++events;});
  sides.start();
  EXPECT(client.wait_for_server(10s));
  auto handle = client.activate(activation_of(10));
  EXPECT(wait_until([&handle]() {return static_cast<bool>(handle->goal_handle());}));
  EXPECT(server.fire(event_of(3)) == 0u);
  EXPECT(server.fire(event_of(12)) == 1u);
  EXPECT(wait_until([&events]() {return events == 1;}));
  bool refused = false;
  try {
    client.activate(activation_of(10), true);
  } catch (const std::invalid_argument &) {
    refused = true;
  }
  EXPECT(refused);
  client.deactivate(handle);
  EXPECT(handle->ended);
  sides.runtime.stop();
}

void an_activation_made_before_the_server_is_there_is_sent_once_it_is()
{
  // a goal sent to no server is lost: so would be every event of its activation
  EventSides sides("late_");
  std::atomic<int> events{0};
  robmosys_runtime::EventClient<Fibonacci> client(
    sides.watcher.get(), "late_event", rclcpp::QoS(10),
    [&events](const Fibonacci::Feedback &) {++events;});
  sides.start();
  auto early = client.activate(activation_of(10));
  auto dropped = client.activate(activation_of(10));
  client.deactivate(dropped);  // deactivated while it waited: never sent
  std::this_thread::sleep_for(500ms);
  EXPECT(!early->goal_handle() && !early->ended);
  robmosys_runtime::EventServer<Fibonacci> server(
    sides.sensor.get(), "late_event", rclcpp::QoS(10), nullptr, reaches);
  // the events of a sensor keep coming: one sent before the server's publisher
  // matched the client's subscription is not the last
  EXPECT(wait_until([&]() {return server.fire(event_of(12)) >= 1u && events >= 1;}));
  EXPECT(server.fire(event_of(12)) == 1u);  // the one that waited, not the dropped one
  EXPECT(dropped->events == 0u && !dropped->goal_handle());
  sides.runtime.stop();
}

void an_activation_its_server_ended_is_ended_without_its_result()
{
  EventSides sides("resultless_");
  robmosys_runtime::EventClient<Fibonacci> client(
    sides.watcher.get(), "resultless_event", rclcpp::QoS(10));
  sides.start();
  // activated before the server is there: sent once the server has matched the client
  auto handle = client.activate(activation_of(1));
  ResultlessServer server(sides.sensor.get(), "resultless_event");
  EXPECT(wait_until([&handle]() {return static_cast<bool>(handle->goal_handle());}));
  EXPECT(server.goals() == 1u && !handle->ended);
  server.abort();
  // the goal's status tells it
  EXPECT(wait_until([&handle]() {return handle->ended.load();}));
  EXPECT(!handle->finished);
  // deactivating an activation its server ended cancels nothing, and does not throw
  client.deactivate(handle);
  EXPECT(handle->finished && handle->ended);
  sides.runtime.stop();
}

void component_ports_live_from_configure_to_cleanup()
{
  Runtime runtime;
  auto node = std::make_shared<Counter>();
  runtime.spin(node);
  runtime.start();
  EXPECT(node->pCount == nullptr);
  EXPECT(node->configure().id() == lifecycle_msgs::msg::State::PRIMARY_STATE_INACTIVE);
  EXPECT(node->pCount != nullptr);
  std::this_thread::sleep_for(100ms);
  EXPECT(node->count == 0);  // inactive: the timer does not run
  node->activate();
  EXPECT(node->is_active());
  EXPECT(wait_until([&node]() {return node->count >= 4;}));  // a failing tick went on
  EXPECT(wait_until([&node]() {return node->received >= 3;}));
  node->deactivate();
  const int stopped = node->count;
  std::this_thread::sleep_for(100ms);
  EXPECT(node->count <= stopped + 1);
  node->cleanup();
  EXPECT(node->pCount == nullptr);
  runtime.stop();
}

/// Return the time in a send file of a topic in a directory, 0 if none, -1 if no file.
std::int64_t last_send(const std::string & directory, const std::string & topic)
{
  const std::string prefix = robmosys_runtime::topic_key(topic) + "-";
  std::int64_t last = -1;
  for (const auto & entry : std::filesystem::directory_iterator(directory)) {
    if (entry.path().filename().string().rfind(prefix, 0) == 0) {
      std::ifstream file(entry.path(), std::ios::binary);
      std::int64_t value = 0;
      file.read(reinterpret_cast<char *>(&value), sizeof(value));
      last = std::max(last, value);
    }
  }
  return last;
}

void a_port_keeps_the_time_of_its_last_send_where_bringup_asks()
{
  // the key of a topic is the one robmosys_runtime/sends.py computes
  EXPECT(robmosys_runtime::topic_key("a") == "af63dc4c8601ec8c");
  char pattern[] = "/tmp/robmosys-sends-test-XXXXXX";
  const std::string directory = ::mkdtemp(pattern);
  ::setenv("ROBMOSYS_SENDS", directory.c_str(), 1);
  Runtime runtime;
  auto node = std::make_shared<Counter>();
  runtime.spin(node);
  runtime.start();
  node->configure();
  ::unsetenv("ROBMOSYS_SENDS");
  EXPECT(last_send(directory, "/pCount") == 0);  // a file, nothing sent while inactive
  const auto before = std::chrono::steady_clock::now().time_since_epoch();
  node->activate();
  EXPECT(wait_until([&node]() {return node->count >= 2;}));
  EXPECT(last_send(directory, "/pCount") >= std::chrono::nanoseconds(before).count());
  node->deactivate();
  node->cleanup();
  runtime.stop();
  std::filesystem::remove_all(directory);
}

void queries_are_answered_while_active_only()
{
  Runtime runtime;
  auto node = std::make_shared<Counter>();
  auto asker = std::make_shared<rclcpp::Node>("asker");
  robmosys_runtime::QueryClient<BasicTypes> query(asker->create_client<BasicTypes>("qDouble"));
  runtime.spin(node);
  runtime.spin(asker);
  runtime.start();
  node->configure();
  EXPECT(query.wait_for_service(10s));
  // the service is there; its answers may reach the client a moment later
  std::this_thread::sleep_for(500ms);
  BasicTypes::Request request;
  request.int32_value = 21;
  EXPECT(query.call(request)->int32_value == 0);  // inactive: the default response
  node->activate();
  EXPECT(query.call(request)->int32_value == 42);
  query.call_async(request);  // no callback: nothing runs
  node->deactivate();
  node->cleanup();
  EXPECT(node->qDouble == nullptr);
  runtime.stop();
}

void a_throwing_hook_fails_its_transition()
{
  Runtime runtime;
  auto node = std::make_shared<Counter>();
  node->fail_configure = true;
  runtime.spin(node);
  runtime.start();
  EXPECT(node->configure().id() == lifecycle_msgs::msg::State::PRIMARY_STATE_UNCONFIGURED);
  EXPECT(node->pCount == nullptr);
  runtime.stop();
}

/// Return the message map_entries refuses the entries with, or "" if it accepts them.
std::string map_entries_problem(const std::vector<std::string> & joints)
{
  auto node = std::make_shared<rclcpp_lifecycle::LifecycleNode>("mapped");
  node->declare_parameter("joints", joints);
  node->declare_parameter("wrist.gain", 1.0);
  try {
    EXPECT(robmosys_runtime::map_entries(*node, "joints", {"{}.gain", "gains.{}.p"}) == joints);
  } catch (const std::invalid_argument & error) {
    return error.what();
  }
  return "";
}

void mapped_entries_are_checked_as_the_model_checks_them()
{
  Runtime runtime;
  EXPECT(robmosys_runtime::mapped_name("gains.{}.p", "elbow") == "gains.elbow.p");
  EXPECT(map_entries_problem({"shoulder", "elbow"}).empty());
  EXPECT(map_entries_problem({"a", "a"}) == "parameter 'joints': entry 'a' is listed twice");
  EXPECT(
    map_entries_problem({"a__b"}) == "parameter 'joints': entry 'a__b' is not a parameter "
    "name part (a letter, then letters, digits and single underscores)");
  EXPECT(!map_entries_problem({"1a"}).empty());
  EXPECT(!map_entries_problem({"a.b"}).empty());
  EXPECT(
    map_entries_problem({"wrist"}) == "parameter 'joints': entry 'wrist' gives the parameter "
    "'wrist.gain', which the component has");
}

int main()
{
  for (const auto & test : std::vector<std::function<void()>>{
    query_client, events_reach_the_activations_whose_condition_holds,
    an_activation_made_before_the_server_is_there_is_sent_once_it_is,
    an_activation_its_server_ended_is_ended_without_its_result,
    component_ports_live_from_configure_to_cleanup, queries_are_answered_while_active_only,
    a_throwing_hook_fails_its_transition, mapped_entries_are_checked_as_the_model_checks_them,
    a_port_keeps_the_time_of_its_last_send_where_bringup_asks})
  {
    try {
      test();
    } catch (const std::exception & error) {
      std::fprintf(stderr, "test_runtime.cpp: unexpected exception: %s\n", error.what());
      ++failures;
    }
  }
  std::fprintf(stderr, "%d check(s) failed\n", failures);
  return failures == 0 ? 0 : 1;
}
