# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
#
# Build a test program, then run it: cmake -DBUILD_DIR=... -DTARGET=... -DPROGRAM=... -P
# this file. The program is left out of `all`, so that `colcon build` of every workspace
# that gets this package does not compile it; `colcon test` does, when it runs the test.

execute_process(
  COMMAND "${CMAKE_COMMAND}" --build "${BUILD_DIR}" --target "${TARGET}"
  RESULT_VARIABLE built)
if(NOT built EQUAL 0)
  message(FATAL_ERROR "building ${TARGET} failed (${built})")
endif()
execute_process(COMMAND "${PROGRAM}" RESULT_VARIABLE ran)
if(NOT ran EQUAL 0)
  message(FATAL_ERROR "${TARGET} failed (${ran})")
endif()
