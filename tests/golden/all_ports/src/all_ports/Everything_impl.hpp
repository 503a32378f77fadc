// Your implementation of the component Everything: this file is yours.
// colcon-robmosys created it once and never writes it again; the skeleton
// src-skel/all_ports/Everything_impl.hpp of the generated package shows
// what the model asks for after the model changes.
// Copyright and license: those of the package all_ports (package.xml).

#pragma once

#include <memory>

#include "all_ports/Everything.hpp"

namespace all_ports
{

/// The component Everything with its user-written functions.
class Everything_impl : public Everything
{
public:
  using Everything::Everything;

protected:
  void fOnTick(const all_ports_msgs::msg::Tick & commobj) override;
  void fAnswer(const all_ports_msgs::srv::Twice::Response & commobj) override;
  all_ports_msgs::action::Count::Result fCount(
    const std::shared_ptr<GoalHandle_aCount> goal_handle) override;
  void fResult(const all_ports_msgs::action::Count::Result & commobj) override;
  void fOnLevel(const all_ports_msgs::action::Level::Feedback & commobj) override;
  void fSetUp() override;
  void fTearDown() override;
};

}  // namespace all_ports
