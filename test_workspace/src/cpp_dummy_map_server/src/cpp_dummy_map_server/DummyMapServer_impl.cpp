// Your implementation of the component DummyMapServer: this file is yours.
// colcon-robmosys created it once and never writes it again; the skeleton
// src-skel/cpp_dummy_map_server/DummyMapServer_impl.cpp of the generated package shows
// what the model asks for after the model changes.
// Copyright and license: those of the package cpp_dummy_map_server (package.xml).

#include "cpp_dummy_map_server/DummyMapServer_impl.hpp"

#include <cstddef>
#include <cstdint>
#include <memory>

namespace cpp_dummy_map_server
{

// Prepare a map of the size of the parameters, with a border of obstacles.
void DummyMapServer_impl::fInit()
{
  const auto width = static_cast<uint32_t>(params().width());
  const auto height = static_cast<uint32_t>(params().height());
  msg_ = nav_msgs::msg::OccupancyGrid();
  msg_.header.frame_id = params().frame_id();
  msg_.info.width = width;
  msg_.info.height = height;
  msg_.info.resolution = static_cast<float>(params().resolution());
  msg_.data.reserve(static_cast<std::size_t>(width) * height);
  for (uint32_t y = 0; y < height; ++y) {
    for (uint32_t x = 0; x < width; ++x) {
      const bool border = x == 0 || x == width - 1 || y == 0 || y == height - 1;
      msg_.data.push_back(border ? 100 : 0);
    }
  }
}

// Stamp and publish the map.
void DummyMapServer_impl::fPublish()
{
  msg_.header.stamp = now();
  map->publish(msg_);
}

}  // namespace cpp_dummy_map_server
