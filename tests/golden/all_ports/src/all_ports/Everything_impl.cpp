// Your implementation of the component Everything: this file is yours.
// colcon-robmosys created it once and never writes it again; the skeleton
// src-skel/all_ports/Everything_impl.cpp of the generated package shows
// what the model asks for after the model changes.
// Copyright and license: those of the package all_ports (package.xml).

#include "all_ports/Everything_impl.hpp"

#include <memory>

namespace all_ports
{

// The function fOnTick of the model.
void Everything_impl::fOnTick(const all_ports_msgs::msg::Tick & commobj)
{
  static_cast<void>(commobj);
  RCLCPP_WARN(get_logger(), "fOnTick is not implemented yet");
}

// The function fAnswer of the model.
void Everything_impl::fAnswer(const all_ports_msgs::srv::Twice::Response & commobj)
{
  static_cast<void>(commobj);
  RCLCPP_WARN(get_logger(), "fAnswer is not implemented yet");
}

// The function fCount of the model.
all_ports_msgs::action::Count::Result Everything_impl::fCount(
  const std::shared_ptr<GoalHandle_aCount> goal_handle)
{
  static_cast<void>(goal_handle);
  RCLCPP_WARN(get_logger(), "fCount is not implemented yet");
  return all_ports_msgs::action::Count::Result();
}

// The function fResult of the model.
void Everything_impl::fResult(const all_ports_msgs::action::Count::Result & commobj)
{
  static_cast<void>(commobj);
  RCLCPP_WARN(get_logger(), "fResult is not implemented yet");
}

// The function fOnLevel of the model.
void Everything_impl::fOnLevel(const all_ports_msgs::action::Level::Feedback & commobj)
{
  static_cast<void>(commobj);
  RCLCPP_WARN(get_logger(), "fOnLevel is not implemented yet");
}

// The function fSetUp of the model.
void Everything_impl::fSetUp()
{
  RCLCPP_WARN(get_logger(), "fSetUp is not implemented yet");
}

// The function fTearDown of the model.
void Everything_impl::fTearDown()
{
  RCLCPP_WARN(get_logger(), "fTearDown is not implemented yet");
}

}  // namespace all_ports
