// Your implementation of the component Client: this file is yours.
// colcon-robmosys created it once and never writes it again; the skeleton
// src-skel/cpp_client/Client_impl.cpp of the generated package shows
// what the model asks for after the model changes.
// Copyright and license: those of the package cpp_client (package.xml).

#include "cpp_client/Client_impl.hpp"

#include <chrono>
#include <exception>
#include <memory>
#include <string>

namespace cpp_client
{

// Ask n + 1000 and wait for the answer, then n + 2000 without waiting.
void Client_impl::fAsk()
{
  ++n_;
  example_msgs::srv::AddTwoInts::Request request;
  request.a = n_;
  request.b = 1000;
  try {
    auto answer = qAdd->call(request, std::chrono::seconds(2));
    RCLCPP_INFO(
      get_logger(), "blocking answer: %s + 1000 = %s", std::to_string(n_).c_str(),
      std::to_string(answer->sum).c_str());
  } catch (const std::exception & error) {
    RCLCPP_WARN(get_logger(), "no answer: %s", error.what());
    return;
  }
  request.b = 2000;
  qAdd->call_async(request);
}

// Count from 1 again.
void Client_impl::fReset()
{
  n_ = 0;
}

}  // namespace cpp_client
