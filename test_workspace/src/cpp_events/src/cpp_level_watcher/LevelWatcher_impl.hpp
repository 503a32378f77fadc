// Your implementation of the component LevelWatcher: this file is yours.
// colcon-robmosys created it once and never writes it again; the skeleton
// src-skel/cpp_level_watcher/LevelWatcher_impl.hpp of the generated package shows
// what the model asks for after the model changes.
// Copyright and license: those of the package cpp_level_watcher (package.xml).

#pragma once

#include <memory>

#include "cpp_level_watcher/LevelWatcher.hpp"

namespace cpp_level_watcher
{

/// The component LevelWatcher with its user-written functions.
class LevelWatcher_impl : public LevelWatcher
{
public:
  using LevelWatcher::LevelWatcher;

protected:
  void fWatch() override;
  void fForget() override;

private:
  using Activation = ports::EventActivation<example_msgs::action::LevelAbove>;
  /// The activations of the event, made once the sensor is there.
  std::shared_ptr<Activation> continuous_;
  std::shared_ptr<Activation> single_;
};

}  // namespace cpp_level_watcher
