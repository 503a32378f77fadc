// Your implementation of the component DummyJointStates: this file is yours.
// colcon-robmosys created it once and never writes it again; the skeleton
// src-skel/cpp_dummy_joint_states/DummyJointStates_impl.hpp of the generated package shows
// what the model asks for after the model changes.
// Copyright and license: those of the package cpp_dummy_joint_states (package.xml).

#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "cpp_dummy_joint_states/DummyJointStates.hpp"
#include "sensor_msgs/msg/joint_state.hpp"

namespace cpp_dummy_joint_states
{

/// The component DummyJointStates with its user-written functions.
class DummyJointStates_impl : public DummyJointStates
{
public:
  using DummyJointStates::DummyJointStates;

protected:
  void fInit() override;
  void fPublish() override;

private:
  sensor_msgs::msg::JointState msg_;
  int64_t counter_{0};
  /// The amplitude of each joint, by its place in msg_ (parameters <joint>.amplitude).
  std::vector<double> amplitudes_;
};

}  // namespace cpp_dummy_joint_states
