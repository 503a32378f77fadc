// Your implementation of the component Receiver: this file is yours.
// colcon-robmosys created it once and never writes it again; the skeleton
// src-skel/cpp_receiver/Receiver_impl.hpp of the generated package shows
// what the model asks for after the model changes.
// Copyright and license: those of the package cpp_receiver (package.xml).

#pragma once

#include <memory>

#include "cpp_receiver/Receiver.hpp"

namespace cpp_receiver
{

/// The component Receiver with its user-written functions.
class Receiver_impl : public Receiver
{
public:
  using Receiver::Receiver;

protected:
  void fReceiving(const simple_msgs::msg::Map & commobj) override;
};

}  // namespace cpp_receiver
