// Your implementation of the component Server: this file is yours.
// colcon-robmosys created it once and never writes it again; the skeleton
// src-skel/cpp_server/Server_impl.cpp of the generated package shows
// what the model asks for after the model changes.
// Copyright and license: those of the package cpp_server (package.xml).

#include "cpp_server/Server_impl.hpp"

#include <memory>
#include <string>

namespace cpp_server
{

// Answer width times height.
void Server_impl::fCount(
  const simple_msgs::srv::CountCells::Request & request,
  simple_msgs::srv::CountCells::Response & response)
{
  response.cells = static_cast<uint64_t>(request.width) * request.height;
  RCLCPP_INFO(
    get_logger(), "%u x %u: %s cells", request.width, request.height,
    std::to_string(response.cells).c_str());
}

}  // namespace cpp_server
