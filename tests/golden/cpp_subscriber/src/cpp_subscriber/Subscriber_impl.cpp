// Your implementation of the component Subscriber: this file is yours.
// colcon-robmosys created it once and never writes it again; the skeleton
// src-skel/cpp_subscriber/Subscriber_impl.cpp of the generated package shows
// what the model asks for after the model changes.
// Copyright and license: those of the package cpp_subscriber (package.xml).

#include "cpp_subscriber/Subscriber_impl.hpp"

#include <memory>

namespace cpp_subscriber
{

// Print the size of each map received.
void Subscriber_impl::fListening(const simple_msgs::msg::Map & commobj)
{
  RCLCPP_INFO(
    get_logger(), "got map data: width %u, height %u, resolution %.2f",
    commobj.ogm.width, commobj.ogm.height, commobj.ogm.resolution);
}

}  // namespace cpp_subscriber
