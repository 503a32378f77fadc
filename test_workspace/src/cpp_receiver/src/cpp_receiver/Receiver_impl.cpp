// Your implementation of the component Receiver: this file is yours.
// colcon-robmosys created it once and never writes it again; the skeleton
// src-skel/cpp_receiver/Receiver_impl.cpp of the generated package shows
// what the model asks for after the model changes.
// Copyright and license: those of the package cpp_receiver (package.xml).

#include "cpp_receiver/Receiver_impl.hpp"

#include <memory>

namespace cpp_receiver
{

// Print the size of each map received.
void Receiver_impl::fReceiving(const simple_msgs::msg::Map & commobj)
{
  RCLCPP_INFO(
    get_logger(), "received map: width %u, height %u", commobj.ogm.width, commobj.ogm.height);
}

}  // namespace cpp_receiver
