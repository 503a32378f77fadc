// Your implementation of the component LevelSensor: this file is yours.
// colcon-robmosys created it once and never writes it again; the skeleton
// src-skel/cpp_level_sensor/LevelSensor_impl.cpp of the generated package shows
// what the model asks for after the model changes.
// Copyright and license: those of the package cpp_level_sensor (package.xml).

#include "cpp_level_sensor/LevelSensor_impl.hpp"

#include <memory>

namespace cpp_level_sensor
{

// Take the next level; it is a candidate event for every activation.
void LevelSensor_impl::fMeasure()
{
  level_ = (level_ + 1) % 20;
  example_msgs::action::LevelAbove::Feedback event;
  event.level = level_;
  const size_t notified = eLevel->fire(event);
  if (notified > 0) {
    RCLCPP_INFO(get_logger(), "level %d notified to %zu", level_, notified);
  }
}

}  // namespace cpp_level_sensor
