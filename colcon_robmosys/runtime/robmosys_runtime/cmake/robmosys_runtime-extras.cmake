# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

# robmosys_runtime_add_component_container()
#
# The component container of a system's shared C++ instances
# (share/robmosys_runtime/src/component_container.cpp: rclcpp_components'
# container, which makes and brings up its instances itself), built and installed
# as lib/<project>/component_container by the system package that calls it, where
# rclcpp_components and the C++ half of robmosys_runtime are installed; otherwise
# it says why there is none. The project has the language CXX.
macro(robmosys_runtime_add_component_container)
  find_package(rclcpp_components QUIET)
  if(rclcpp_components_FOUND AND TARGET robmosys_runtime::robmosys_runtime)
    add_executable(component_container
      "${robmosys_runtime_DIR}/../src/component_container.cpp")
    target_link_libraries(component_container
      robmosys_runtime::robmosys_runtime rclcpp_components::component_manager)
    install(TARGETS component_container DESTINATION lib/${PROJECT_NAME})
  else()
    message(STATUS "${PROJECT_NAME}: no component container for its C++ instances: "
      "rclcpp_components, or the C++ half of robmosys_runtime, is not installed")
  endif()
endmacro()
