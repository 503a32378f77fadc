// Your implementation of the component DummyJointStates: this file is yours.
// colcon-robmosys created it once and never writes it again; the skeleton
// src-skel/cpp_dummy_joint_states/DummyJointStates_impl.cpp of the generated package shows
// what the model asks for after the model changes.
// Copyright and license: those of the package cpp_dummy_joint_states (package.xml).

#include "cpp_dummy_joint_states/DummyJointStates_impl.hpp"

#include <cmath>
#include <cstddef>
#include <memory>

namespace cpp_dummy_joint_states
{

// Prepare the message with the joint names of the parameters.
void DummyJointStates_impl::fInit()
{
  msg_ = sensor_msgs::msg::JointState();
  msg_.name = params().joint_names();
  msg_.position.assign(msg_.name.size(), 0.0);
  amplitudes_.clear();
  const auto joints = params().joint_names_map();
  for (const auto & name : msg_.name) {
    amplitudes_.push_back(joints.at(name).amplitude());
  }
  counter_ = 0;
}

// Move every joint a step along a sine and publish the states.
void DummyJointStates_impl::fPublish()
{
  ++counter_;
  msg_.header.stamp = now();
  const double angle = std::sin(static_cast<double>(counter_) * params().speed());
  for (std::size_t i = 0; i < msg_.position.size(); ++i) {
    msg_.position[i] = angle * amplitudes_[i];
  }
  joint_states->publish(msg_);
}

}  // namespace cpp_dummy_joint_states
