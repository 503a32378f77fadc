// Copyright 2026 The colcon-robmosys authors
// Licensed under the Apache License, Version 2.0

/// \file Copies between message types of the same fields.

#ifndef ROBMOSYS_RUNTIME__MESSAGE_COPY_HPP_
#define ROBMOSYS_RUNTIME__MESSAGE_COPY_HPP_

#include <stdexcept>
#include <type_traits>
#include <utility>

#include "rclcpp/serialization.hpp"
#include "rclcpp/serialized_message.hpp"

namespace robmosys_runtime
{

/// Copy a message into another type of the same fields, through their CDR form.
/**
 * The result and the feedback of an event's action both hold the event's fields.
 */
template<typename FromT, typename ToT>
ToT convert(const FromT & from)
{
  rclcpp::SerializedMessage serialized;
  rclcpp::Serialization<FromT>().serialize_message(&from, &serialized);
  ToT to;
  rclcpp::Serialization<ToT>().deserialize_message(&serialized, &to);
  return to;
}

namespace detail
{

/// Whether an activation type has the field single (event types written by hand may not).
template<typename GoalT, typename = void>
struct has_single : std::false_type {};

template<typename GoalT>
struct has_single<GoalT, std::void_t<decltype(std::declval<GoalT &>().single)>>
  : std::true_type {};

}  // namespace detail

/// Return whether an activation asks for one event only.
template<typename GoalT>
bool is_single(const GoalT & activation)
{
  if constexpr (detail::has_single<GoalT>::value) {
    return activation.single;
  } else {
    static_cast<void>(activation);
    return false;
  }
}

/// Ask an activation for one event only, or for every event.
/**
 * \throws std::invalid_argument if single is asked of a type without the field
 */
template<typename GoalT>
void set_single(GoalT & activation, bool single)
{
  if constexpr (detail::has_single<GoalT>::value) {
    activation.single = single;
  } else {
    static_cast<void>(activation);
    if (single) {
      throw std::invalid_argument("the activations of this event have no single field");
    }
  }
}

}  // namespace robmosys_runtime

#endif  // ROBMOSYS_RUNTIME__MESSAGE_COPY_HPP_
