// Your implementation of the component Server: this file is yours.
// colcon-robmosys created it once and never writes it again; the skeleton
// src-skel/cpp_server/Server_impl.hpp of the generated package shows
// what the model asks for after the model changes.
// Copyright and license: those of the package cpp_server (package.xml).

#pragma once

#include <memory>

#include "cpp_server/Server.hpp"

namespace cpp_server
{

/// The component Server with its user-written functions.
class Server_impl : public Server
{
public:
  using Server::Server;

protected:
  void fAdd(
    const example_msgs::srv::AddTwoInts::Request & request,
    example_msgs::srv::AddTwoInts::Response & response) override;
};

}  // namespace cpp_server
