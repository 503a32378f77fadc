// Your implementation of the component DummyLaser: this file is yours.
// colcon-robmosys created it once and never writes it again; the skeleton
// src-skel/cpp_dummy_laser/DummyLaser_impl.cpp of the generated package shows
// what the model asks for after the model changes.
// Copyright and license: those of the package cpp_dummy_laser (package.xml).

#include "cpp_dummy_laser/DummyLaser_impl.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <memory>

namespace cpp_dummy_laser
{

// Prepare the scan from the parameters.
void DummyLaser_impl::fInit()
{
  const double pi = std::acos(-1.0);
  msg_ = sensor_msgs::msg::LaserScan();
  msg_.header.frame_id = params().frame_id();
  msg_.angle_min = static_cast<float>(-pi / 2);
  msg_.angle_max = static_cast<float>(pi / 2);
  const int64_t steps = std::max<int64_t>(params().samples() - 1, 1);
  msg_.angle_increment = static_cast<float>(pi / static_cast<double>(steps));
  msg_.range_min = 0.0F;
  msg_.range_max = static_cast<float>(params().range_max());
  count_ = 0;
}

// Fill the ranges and publish the scan.
void DummyLaser_impl::fScan()
{
  ++count_;
  msg_.header.stamp = now();
  const double middle = params().range_max() / 2;
  const auto samples = static_cast<std::size_t>(params().samples());
  msg_.ranges.resize(samples);
  for (std::size_t i = 0; i < samples; ++i) {
    const double phase = static_cast<double>(count_) * 0.1 + static_cast<double>(i) * 0.01;
    msg_.ranges[i] = static_cast<float>(middle + middle * std::sin(phase));
  }
  scan->publish(msg_);
}

}  // namespace cpp_dummy_laser
