# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

"""Map checked RobMoSys models to ROS 2: one language-neutral plan per package.

The port-kind table (portkinds) says what each port becomes; component,
system and interfaces build the plans; cpp and python spell a component
plan in their language. Every ROS 2 decision lives here.
"""
