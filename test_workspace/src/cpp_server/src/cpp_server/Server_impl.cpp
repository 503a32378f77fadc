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

// Answer a request with the sum.
void Server_impl::fAdd(
  const example_msgs::srv::AddTwoInts::Request & request,
  example_msgs::srv::AddTwoInts::Response & response)
{
  response.sum = request.a + request.b;
  RCLCPP_INFO(
    get_logger(), "answering %s + %s", std::to_string(request.a).c_str(),
    std::to_string(request.b).c_str());
}

}  // namespace cpp_server
