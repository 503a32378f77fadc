// Copyright 2026 The colcon-robmosys authors
// Licensed under the Apache License, Version 2.0
//
// The hand-written Listener as an rclcpp_components library: what bench_cppbuild.py
// builds against the generated C++ Listener (its executable comes from
// rclcpp_components_register_node).

#include "rclcpp_components/register_node_macro.hpp"

#include "pubsub_nodes.hpp"

RCLCPP_COMPONENTS_REGISTER_NODE(bench_handwritten::Listener)
