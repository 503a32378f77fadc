// Your implementation of the component DummyMapServer: this file is yours.
// colcon-robmosys created it once and never writes it again; the skeleton
// src-skel/cpp_dummy_map_server/DummyMapServer_impl.hpp of the generated package shows
// what the model asks for after the model changes.
// Copyright and license: those of the package cpp_dummy_map_server (package.xml).

#pragma once

#include <memory>

#include "cpp_dummy_map_server/DummyMapServer.hpp"
#include "nav_msgs/msg/occupancy_grid.hpp"

namespace cpp_dummy_map_server
{

/// The component DummyMapServer with its user-written functions.
class DummyMapServer_impl : public DummyMapServer
{
public:
  using DummyMapServer::DummyMapServer;

protected:
  void fInit() override;
  void fPublish() override;

private:
  nav_msgs::msg::OccupancyGrid msg_;
};

}  // namespace cpp_dummy_map_server
