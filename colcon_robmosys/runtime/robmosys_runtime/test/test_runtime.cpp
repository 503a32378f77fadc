// Copyright 2026 The colcon-robmosys authors
// Licensed under the Apache License, Version 2.0

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <functional>
#include <memory>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "rclcpp/rclcpp.hpp"
#include "rclcpp_action/rclcpp_action.hpp"
#include "std_msgs/msg/int32.hpp"
#include "test_msgs/action/fibonacci.hpp"
#include "test_msgs/srv/basic_types.hpp"

#include "robmosys_runtime/action_client.hpp"
#include "robmosys_runtime/component_node.hpp"
#include "robmosys_runtime/event_client.hpp"
#include "robmosys_runtime/event_server.hpp"
#include "robmosys_runtime/main.hpp"
#include "robmosys_runtime/query_client.hpp"

using namespace std::chrono_literals;
using Fibonacci = test_msgs::action::Fibonacci;
using BasicTypes = test_msgs::srv::BasicTypes;

namespace
{

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

/// rclcpp, and an executor spinning in a thread.
class Runtime : public ::testing::Test
{
protected:
  void SetUp() override
  {
    rclcpp::init(0, nullptr);
    executor_ = std::make_shared<rclcpp::executors::MultiThreadedExecutor>(
      rclcpp::ExecutorOptions(), 4);
  }

  void TearDown() override
  {
    executor_->cancel();
    if (spinner_.joinable()) {
      spinner_.join();
    }
    executor_.reset();
    rclcpp::shutdown();
  }

  template<typename NodeT>
  void spin(const std::shared_ptr<NodeT> & node)
  {
    executor_->add_node(node->get_node_base_interface());
  }

  void start()
  {
    spinner_ = std::thread([this]() {executor_->spin();});
  }

  std::shared_ptr<rclcpp::executors::MultiThreadedExecutor> executor_;
  std::thread spinner_;
};

/// A component that counts periodically and publishes the count.
class Counter : public robmosys_runtime::ComponentNode
{
public:
  Counter()
  : ComponentNode("counter", rclcpp::NodeOptions())
  {
    add_activity("Tick");
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
  std::shared_ptr<rclcpp_lifecycle::LifecyclePublisher<std_msgs::msg::Int32>> pCount;

protected:
  void create_ports() override
  {
    keep_publisher(pCount, create_publisher<std_msgs::msg::Int32>("pCount", 10));
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

}  // namespace

TEST_F(Runtime, query_and_action_clients)
{
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
  spin(server);
  spin(client_node);
  start();
  ASSERT_TRUE(query.wait_for_service(10s));
  BasicTypes::Request request;
  request.int32_value = 5;
  EXPECT_EQ(query.call(request)->int32_value, 1005);
  request.int32_value = 7;
  query.call_async(request);
  EXPECT_TRUE(wait_until([&answered]() {return answered == 1007;}));
}

TEST_F(Runtime, events_reach_the_activations_whose_condition_holds)
{
  auto sensor = std::make_shared<rclcpp::Node>("sensor");
  auto watcher = std::make_shared<rclcpp::Node>("watcher");
  robmosys_runtime::EventServer<Fibonacci> server(
    sensor.get(), "event", rclcpp::QoS(10), nullptr,
    [](const Fibonacci::Goal & activation, const Fibonacci::Feedback & event) {
      return event.sequence.at(0) >= activation.order;
    });
  std::atomic<int> events{0};
  robmosys_runtime::EventClient<Fibonacci> client(
    watcher.get(), "event", rclcpp::QoS(10),
    [&events](const Fibonacci::Feedback &) {++events;});
  spin(sensor);
  spin(watcher);
  start();
  ASSERT_TRUE(client.wait_for_server(10s));
  Fibonacci::Goal activation;
  activation.order = 10;
  auto handle = client.activate(activation);
  ASSERT_TRUE(wait_until([&handle]() {return static_cast<bool>(handle->goal_handle);}));
  Fibonacci::Feedback low, high;
  low.sequence = {3};
  high.sequence = {12};
  EXPECT_EQ(server.fire(low), 0u);
  EXPECT_EQ(server.fire(high), 1u);
  EXPECT_TRUE(wait_until([&events]() {return events == 1;}));
  EXPECT_THROW(client.activate(activation, true), std::invalid_argument);
  client.deactivate(handle);
  EXPECT_TRUE(handle->ended);
}

TEST_F(Runtime, component_ports_live_from_configure_to_cleanup)
{
  auto node = std::make_shared<Counter>();
  spin(node);
  start();
  EXPECT_FALSE(node->pCount);
  ASSERT_EQ(node->configure().id(), lifecycle_msgs::msg::State::PRIMARY_STATE_INACTIVE);
  ASSERT_TRUE(node->pCount);
  std::this_thread::sleep_for(100ms);
  EXPECT_EQ(node->count, 0);  // inactive: the timer does not run
  node->activate();
  EXPECT_TRUE(node->is_active());
  EXPECT_TRUE(wait_until([&node]() {return node->count >= 4;}));  // a failing tick went on
  node->deactivate();
  const int stopped = node->count;
  std::this_thread::sleep_for(100ms);
  EXPECT_LE(node->count, stopped + 1);
  node->cleanup();
  EXPECT_FALSE(node->pCount);
}

TEST_F(Runtime, a_throwing_hook_fails_its_transition)
{
  auto node = std::make_shared<Counter>();
  node->fail_configure = true;
  spin(node);
  start();
  EXPECT_EQ(node->configure().id(), lifecycle_msgs::msg::State::PRIMARY_STATE_UNCONFIGURED);
  EXPECT_FALSE(node->pCount);
}
