// Copyright 2026 The colcon-robmosys authors
// Licensed under the Apache License, Version 2.0
//
// The user code of the generated C++ listener of bench_runtime.py: what the `code`
// of the Python listener's functions does (bench_runtime.LISTENER), in C++.

#pragma once

#include <cstdint>
#include <vector>

#include "bench_listener_cpp/Listener.hpp"

namespace bench_listener_cpp
{

/// The component Listener with its user-written functions.
class Listener_impl : public Listener
{
public:
  using Listener::Listener;

protected:
  void fSetUp() override;
  void fReceive(const std_msgs::msg::Header & commobj) override;
  void fReport() override;

private:
  int64_t warmup_ns_ = 0;
  std::vector<int64_t> latencies_;
  int64_t first_ = 0;
  int64_t start_ = 0;
  int64_t last_ = 0;
};

}  // namespace bench_listener_cpp
