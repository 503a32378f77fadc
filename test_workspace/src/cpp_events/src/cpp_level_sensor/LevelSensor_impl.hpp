// Your implementation of the component LevelSensor: this file is yours.
// colcon-robmosys created it once and never writes it again; the skeleton
// src-skel/cpp_level_sensor/LevelSensor_impl.hpp of the generated package shows
// what the model asks for after the model changes.
// Copyright and license: those of the package cpp_level_sensor (package.xml).

#pragma once

#include <memory>

#include "cpp_level_sensor/LevelSensor.hpp"

namespace cpp_level_sensor
{

/// The component LevelSensor with its user-written functions.
class LevelSensor_impl : public LevelSensor
{
public:
  using LevelSensor::LevelSensor;

protected:
  void fMeasure() override;

private:
  /// The last level measured.
  int32_t level_ = -1;
};

}  // namespace cpp_level_sensor
