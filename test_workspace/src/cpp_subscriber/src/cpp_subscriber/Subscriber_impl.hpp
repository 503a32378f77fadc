// Your implementation of the component Subscriber: this file is yours.
// colcon-robmosys created it once and never writes it again; the skeleton
// src-skel/cpp_subscriber/Subscriber_impl.hpp of the generated package shows
// what the model asks for after the model changes.
// Copyright and license: those of the package cpp_subscriber (package.xml).

#pragma once

#include <memory>

#include "cpp_subscriber/Subscriber.hpp"

namespace cpp_subscriber
{

/// The component Subscriber with its user-written functions.
class Subscriber_impl : public Subscriber
{
public:
  using Subscriber::Subscriber;

protected:
  void fListening(const simple_msgs::msg::Map & commobj) override;
};

}  // namespace cpp_subscriber
