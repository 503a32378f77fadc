// Copyright 2026 The colcon-robmosys authors
// Licensed under the Apache License, Version 2.0
//
// The user code of the generated C++ talker of bench_runtime.py: what the `code`
// of the Python talker's functions does (bench_runtime.TALKER), in C++.

#pragma once

#include <cstdint>
#include <string>

#include "bench_talker_cpp/Talker.hpp"

namespace bench_talker_cpp
{

/// The component Talker with its user-written functions.
class Talker_impl : public Talker
{
public:
  using Talker::Talker;

protected:
  void fSetUp() override;
  void fPublish() override;
  void fReport() override;

private:
  int64_t burst_ = 1;
  std::string frame_;
  int64_t sent_ = 0;
  int64_t first_ = 0;
  int64_t last_ = 0;
};

}  // namespace bench_talker_cpp
