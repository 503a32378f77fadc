// Your implementation of the component LevelWatcher: this file is yours.
// colcon-robmosys created it once and never writes it again; the skeleton
// src-skel/cpp_level_watcher/LevelWatcher_impl.cpp of the generated package shows
// what the model asks for after the model changes.
// Copyright and license: those of the package cpp_level_watcher (package.xml).

#include "cpp_level_watcher/LevelWatcher_impl.hpp"

#include <chrono>
#include <memory>

namespace cpp_level_watcher
{

// Activate the event once the sensor is there; report the single activation.
void LevelWatcher_impl::fWatch()
{
  if (!continuous_) {
    if (!eLevel->wait_for_server(std::chrono::milliseconds(100))) {
      return;
    }
    example_msgs::action::LevelAbove::Goal activation;
    activation.threshold = static_cast<int32_t>(params().threshold());
    continuous_ = eLevel->activate(activation);
    single_ = eLevel->activate(activation, true);
  }
  auto report = [this](const char * name, const std::shared_ptr<Activation> & handle) {
      RCLCPP_INFO(
        get_logger(), "%s activation: %zu event(s), ended: %s", name, handle->events.load(),
        handle->ended ? "true" : "false");
    };
  report("single", single_);
  report("continuous", continuous_);
}

// The activations end with the port.
void LevelWatcher_impl::fForget()
{
  continuous_.reset();
  single_.reset();
}

}  // namespace cpp_level_watcher
