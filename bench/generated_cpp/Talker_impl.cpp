// Copyright 2026 The colcon-robmosys authors
// Licensed under the Apache License, Version 2.0

#include "bench_talker_cpp/Talker_impl.hpp"

#include <chrono>
#include <iostream>
#include <string>

namespace bench_talker_cpp
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

void Talker_impl::fSetUp()
{
  burst_ = params().burst();
  frame_ = std::string(static_cast<size_t>(params().payload()), 'x');
  sent_ = 0;
  first_ = last_ = 0;
}

void Talker_impl::fPublish()
{
  int64_t now = 0;
  for (int64_t i = 0; i < burst_; ++i) {
    now = now_ns();
    std_msgs::msg::Header message;
    message.frame_id = frame_;
    message.stamp.sec = static_cast<int32_t>(now / 1000000000);
    message.stamp.nanosec = static_cast<uint32_t>(now % 1000000000);
    pSample->publish(message);
  }
  sent_ += burst_;
  first_ = first_ ? first_ : now;
  last_ = now;
}

void Talker_impl::fReport()
{
  std::cout << "BENCH talker {\"sent\": " << sent_ << ", \"first\": " << first_ <<
    ", \"last\": " << last_ << "}" << std::endl;
}

}  // namespace bench_talker_cpp
