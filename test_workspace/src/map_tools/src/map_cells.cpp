// Copyright 2026 The colcon-robmosys authors
// Licensed under the Apache License, Version 2.0

#include <cstdlib>
#include <iostream>

#include "simple_msgs/msg/map.hpp"

// Print the number of cells of a map of the given size: proof that the
// generated message package serves hand-written C++ code.
int main(int argc, char ** argv)
{
  simple_msgs::msg::Map map;
  map.ogm.width = argc > 1 ? static_cast<uint32_t>(std::atoi(argv[1])) : 16;
  map.ogm.height = argc > 2 ? static_cast<uint32_t>(std::atoi(argv[2])) : 16;
  map.ogm.data.assign(map.ogm.width * map.ogm.height, -1);
  std::cout << "cells: " << map.ogm.data.size() << std::endl;
  return 0;
}
