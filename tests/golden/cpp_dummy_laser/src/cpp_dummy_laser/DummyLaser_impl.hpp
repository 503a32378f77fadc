// Your implementation of the component DummyLaser: this file is yours.
// colcon-robmosys created it once and never writes it again; the skeleton
// src-skel/cpp_dummy_laser/DummyLaser_impl.hpp of the generated package shows
// what the model asks for after the model changes.
// Copyright and license: those of the package cpp_dummy_laser (package.xml).

#pragma once

#include <cstdint>
#include <memory>

#include "cpp_dummy_laser/DummyLaser.hpp"
#include "sensor_msgs/msg/laser_scan.hpp"

namespace cpp_dummy_laser
{

/// The component DummyLaser with its user-written functions.
class DummyLaser_impl : public DummyLaser
{
public:
  using DummyLaser::DummyLaser;

protected:
  void fInit() override;
  void fScan() override;

private:
  sensor_msgs::msg::LaserScan msg_;
  int64_t count_{0};
};

}  // namespace cpp_dummy_laser
