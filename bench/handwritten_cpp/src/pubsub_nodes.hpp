// Copyright 2026 The colcon-robmosys authors
// Licensed under the Apache License, Version 2.0
//
// The hand-written rclcpp_lifecycle publisher/subscriber pair of the benchmarks: the
// nodes of pubsub.cpp (bench_runtime.py) and of the rclcpp_components libraries of
// talker.cpp and listener.cpp (bench_cppbuild.py). See pubsub.cpp for what they do.

#ifndef PUBSUB_NODES_HPP_
#define PUBSUB_NODES_HPP_

#include <atomic>
#include <chrono>
#include <cstdint>
#include <iostream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "rclcpp/rclcpp.hpp"
#include "rclcpp_lifecycle/lifecycle_node.hpp"
#include "rclcpp_lifecycle/lifecycle_publisher.hpp"
#include "std_msgs/msg/header.hpp"

namespace bench_handwritten
{

using CallbackReturn =
  rclcpp_lifecycle::node_interfaces::LifecycleNodeInterface::CallbackReturn;

/// keep_last 10, reliable, volatile, automatic liveliness.
inline rclcpp::QoS bench_qos()
{
  rclcpp::QoS qos(rclcpp::KeepLast(10));
  qos.reliable();
  qos.durability_volatile();
  qos.liveliness(RMW_QOS_POLICY_LIVELINESS_AUTOMATIC);
  return qos;
}

/// Nanoseconds since the epoch, like Python's time.time_ns().
inline int64_t now_ns()
{
  return std::chrono::duration_cast<std::chrono::nanoseconds>(
    std::chrono::system_clock::now().time_since_epoch()).count();
}

/// Publishes `burst` stamped headers every 10 ms while active.
class Talker : public rclcpp_lifecycle::LifecycleNode
{
public:
  explicit Talker(const rclcpp::NodeOptions & options = rclcpp::NodeOptions())
  : rclcpp_lifecycle::LifecycleNode("Talker", options)
  {
    declare_parameter<int64_t>("burst", 1);
    declare_parameter<int64_t>("payload", 0);
    group_ = create_callback_group(rclcpp::CallbackGroupType::MutuallyExclusive);
  }

protected:
  CallbackReturn on_configure(const rclcpp_lifecycle::State &) override
  {
    publisher_ = create_publisher<std_msgs::msg::Header>("pSample", bench_qos());
    timer_ = create_wall_timer(std::chrono::milliseconds(10), [this]() {publish();}, group_);
    timer_->cancel();
    burst_ = get_parameter("burst").as_int();
    frame_ = std::string(static_cast<size_t>(get_parameter("payload").as_int()), 'x');
    sent_ = first_ = last_ = 0;
    return CallbackReturn::SUCCESS;
  }

  CallbackReturn on_activate(const rclcpp_lifecycle::State &) override
  {
    publisher_->on_activate();
    active_ = true;
    timer_->reset();
    return CallbackReturn::SUCCESS;
  }

  CallbackReturn on_deactivate(const rclcpp_lifecycle::State &) override
  {
    active_ = false;
    timer_->cancel();
    publisher_->on_deactivate();
    std::cout << "BENCH talker {\"sent\": " << sent_ << ", \"first\": " << first_ <<
      ", \"last\": " << last_ << "}" << std::endl;
    return CallbackReturn::SUCCESS;
  }

  CallbackReturn on_cleanup(const rclcpp_lifecycle::State &) override
  {
    release();
    return CallbackReturn::SUCCESS;
  }

  CallbackReturn on_shutdown(const rclcpp_lifecycle::State &) override
  {
    release();
    return CallbackReturn::SUCCESS;
  }

private:
  void release()
  {
    active_ = false;
    if (timer_) {
      timer_->cancel();
      timer_.reset();
    }
    publisher_.reset();
  }

  void publish()
  {
    if (!active_ || !publisher_) {
      return;
    }
    int64_t now = 0;
    for (int64_t i = 0; i < burst_; ++i) {
      now = now_ns();
      std_msgs::msg::Header message;
      message.frame_id = frame_;
      message.stamp.sec = static_cast<int32_t>(now / 1000000000);
      message.stamp.nanosec = static_cast<uint32_t>(now % 1000000000);
      publisher_->publish(message);
    }
    sent_ += burst_;
    first_ = first_ ? first_ : now;
    last_ = now;
  }

  rclcpp::CallbackGroup::SharedPtr group_;
  rclcpp_lifecycle::LifecyclePublisher<std_msgs::msg::Header>::SharedPtr publisher_;
  rclcpp::TimerBase::SharedPtr timer_;
  std::atomic<bool> active_{false};
  int64_t burst_ = 1;
  std::string frame_;
  int64_t sent_ = 0;
  int64_t first_ = 0;
  int64_t last_ = 0;
};

/// Records the latency of every header received while active, after a warm-up.
class Listener : public rclcpp_lifecycle::LifecycleNode
{
public:
  explicit Listener(const rclcpp::NodeOptions & options = rclcpp::NodeOptions())
  : rclcpp_lifecycle::LifecycleNode("Listener", options)
  {
    declare_parameter<double>("warmup", 0.5);
    group_ = create_callback_group(rclcpp::CallbackGroupType::MutuallyExclusive);
  }

protected:
  CallbackReturn on_configure(const rclcpp_lifecycle::State &) override
  {
    rclcpp::SubscriptionOptions options;
    options.callback_group = group_;
    subscription_ = create_subscription<std_msgs::msg::Header>(
      "rSample", bench_qos(),
      [this](const std_msgs::msg::Header & message) {receive(message);}, options);
    warmup_ns_ = static_cast<int64_t>(get_parameter("warmup").as_double() * 1e9);
    latencies_.clear();
    first_ = start_ = last_ = 0;
    return CallbackReturn::SUCCESS;
  }

  CallbackReturn on_activate(const rclcpp_lifecycle::State &) override
  {
    active_ = true;
    return CallbackReturn::SUCCESS;
  }

  CallbackReturn on_deactivate(const rclcpp_lifecycle::State &) override
  {
    active_ = false;
    std::ostringstream line;
    line << "BENCH listener {\"start\": " << start_ << ", \"last\": " << last_ <<
      ", \"latencies\": [";
    for (size_t i = 0; i < latencies_.size(); ++i) {
      line << (i ? ", " : "") << latencies_[i];
    }
    line << "]}";
    std::cout << line.str() << std::endl;
    return CallbackReturn::SUCCESS;
  }

  CallbackReturn on_cleanup(const rclcpp_lifecycle::State &) override
  {
    release();
    return CallbackReturn::SUCCESS;
  }

  CallbackReturn on_shutdown(const rclcpp_lifecycle::State &) override
  {
    release();
    return CallbackReturn::SUCCESS;
  }

private:
  void release()
  {
    active_ = false;
    subscription_.reset();
  }

  void receive(const std_msgs::msg::Header & message)
  {
    if (!active_) {
      return;
    }
    const int64_t now = now_ns();
    if (!first_) {
      first_ = now;
      std::cout << "BENCH listener first" << std::endl;
    }
    if (now - first_ < warmup_ns_) {
      return;
    }
    start_ = start_ ? start_ : now;
    latencies_.push_back(
      now - static_cast<int64_t>(message.stamp.sec) * 1000000000 -
      static_cast<int64_t>(message.stamp.nanosec));
    last_ = now;
  }

  rclcpp::CallbackGroup::SharedPtr group_;
  rclcpp::Subscription<std_msgs::msg::Header>::SharedPtr subscription_;
  std::atomic<bool> active_{false};
  int64_t warmup_ns_ = 0;
  std::vector<int64_t> latencies_;
  int64_t first_ = 0;
  int64_t start_ = 0;
  int64_t last_ = 0;
};

}  // namespace bench_handwritten

#endif  // PUBSUB_NODES_HPP_
