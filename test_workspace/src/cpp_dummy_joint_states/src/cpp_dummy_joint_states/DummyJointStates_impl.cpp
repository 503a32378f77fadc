// Your implementation of the component DummyJointStates: this file is yours.
// colcon-robmosys created it once and never writes it again; the skeleton
// src-skel/cpp_dummy_joint_states/DummyJointStates_impl.cpp of the generated package shows
// what the model asks for after the model changes.
// Copyright and license: those of the package cpp_dummy_joint_states (package.xml).

#include "cpp_dummy_joint_states/DummyJointStates_impl.hpp"

#include <cmath>
#include <memory>

namespace cpp_dummy_joint_states
{

// Prepare the message with the joint names of the parameters.
void DummyJointStates_impl::fInit()
{
  msg_ = sensor_msgs::msg::JointState();
  msg_.name = params().joint_names();
  msg_.position.assign(msg_.name.size(), 0.0);
  counter_ = 0;
}

// Move every joint a step along a sine and publish the states.
void DummyJointStates_impl::fPublish()
{
  ++counter_;
  msg_.header.stamp = now();
  const double angle = std::sin(static_cast<double>(counter_) * params().speed());
  msg_.position.assign(msg_.name.size(), angle);
  joint_states->publish(msg_);
}

}  // namespace cpp_dummy_joint_states
