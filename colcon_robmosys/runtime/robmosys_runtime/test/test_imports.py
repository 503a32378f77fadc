# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""The package's names are imported when used: bringup starts the instances before rclpy."""

import subprocess
import sys

import pytest
import robmosys_runtime
from robmosys_runtime.main import run
from robmosys_runtime.node import ComponentNode


def test_bringup_starts_the_instances_before_it_imports_rclpy():
    # bringup.main starts the processes of the instances with what the
    # module imports, then imports rclpy (a third of a second): importing
    # the module must not import rclpy through the package
    shown = subprocess.run(
        [sys.executable, '-c', 'import sys, robmosys_runtime.system.bringup\n'
         "print(sorted(m for m in sys.modules if m.split('.')[0] == 'rclpy'))"],
        capture_output=True, text=True, timeout=60, check=True)
    assert shown.stdout.strip() == '[]'


def test_bringup_starts_the_instances_before_it_imports_what_it_may_not_need():
    # YAML (a parameter file given), temporary files and ctypes (a host's
    # bringup): 60 ms before the first process starts, where none is needed
    shown = subprocess.run(
        [sys.executable, '-c', 'import sys, robmosys_runtime.system.bringup\n'
         "print(sorted({'yaml', 'tempfile', 'ctypes'} & set(sys.modules)))"],
        capture_output=True, text=True, timeout=60, check=True)
    assert shown.stdout.strip() == '[]'


def test_the_check_of_parameter_files_runs_without_rclpy():
    # check_params runs offline, where the system is installed: no rclpy, no graph
    shown = subprocess.run(
        [sys.executable, '-c', 'import sys, robmosys_runtime.tools.paramcheck\n'
         "print(sorted(m for m in sys.modules if m.split('.')[0] == 'rclpy'))"],
        capture_output=True, text=True, timeout=60, check=True)
    assert shown.stdout.strip() == '[]'


def test_the_names_of_the_package_are_those_of_their_modules():
    assert robmosys_runtime.ComponentNode is ComponentNode
    assert robmosys_runtime.run is run
    for name in robmosys_runtime.__all__:
        assert getattr(robmosys_runtime, name) is not None
    assert set(robmosys_runtime.__all__) <= set(dir(robmosys_runtime))
    with pytest.raises(AttributeError, match="has no attribute 'ComponentNodes'"):
        robmosys_runtime.ComponentNodes
