// Copyright 2026 The colcon-robmosys authors
// Licensed under the Apache License, Version 2.0

#include "bench_listener_cpp/Listener_impl.hpp"

#include <chrono>
#include <iostream>
#include <sstream>

namespace bench_listener_cpp
{

namespace
{

/// Nanoseconds since the epoch, like Python's time.time_ns().
int64_t now_ns()
{
  return std::chrono::duration_cast<std::chrono::nanoseconds>(
    std::chrono::system_clock::now().time_since_epoch()).count();
}

}  // namespace

void Listener_impl::fSetUp()
{
  warmup_ns_ = static_cast<int64_t>(params().warmup() * 1e9);
  latencies_.clear();
  first_ = start_ = last_ = 0;
}

void Listener_impl::fReceive(const std_msgs::msg::Header & commobj)
{
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
    now - static_cast<int64_t>(commobj.stamp.sec) * 1000000000 -
    static_cast<int64_t>(commobj.stamp.nanosec));
  last_ = now;
}

void Listener_impl::fReport()
{
  std::ostringstream line;
  line << "BENCH listener {\"start\": " << start_ << ", \"last\": " << last_ <<
    ", \"latencies\": [";
  for (size_t i = 0; i < latencies_.size(); ++i) {
    line << (i ? ", " : "") << latencies_[i];
  }
  line << "]}";
  std::cout << line.str() << std::endl;
}

}  // namespace bench_listener_cpp
