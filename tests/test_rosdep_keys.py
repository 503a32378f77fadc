# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""System dependencies of a model are rosdep keys of its package.xml, and resolve.

Offline: rosdep 0.27 reads a local source (ROSDEP_SOURCE_PATH naming a list file with
`yaml file://<keys.yaml>`), a `file://` rosdistro index and a ROS_HOME of the test's own.
"""

from __future__ import annotations

from pathlib import Path
import shutil
import xml.etree.ElementTree as ET

import pytest
import yaml

from colcon_robmosys.check import find_model_files, load_workspace
from colcon_robmosys.generators import create_missing_user_files, generate_package
from colcon_robmosys.generators import plan_package
from colcon_robmosys.runtime import runtime_source
from harness.fake_ament import fake_ament_index
from harness.rosdep import ROSDEP, rosdep, rosdep_env

pytestmark = pytest.mark.skipif(not ROSDEP.is_file(), reason='rosdep is not installed')

#: the system dependencies of the models -> the Ubuntu packages rosdep names
SYSTEM = {'eigen': 'libeigen3-dev', 'python3-numpy': 'python3-numpy',
          'yaml-cpp': 'libyaml-cpp-dev'}


def _component(name: str, package: str, language: str, system: list[str]) -> dict:
    return {'name': name, 'package': package, 'language': language,
            'license': 'Apache-2.0', 'maintainers': [{'name': 'A', 'email': 'a@example.com'}],
            'depends': ['std_msgs'], 'system_depends': system,
            'ports': {'pOut': {'pattern': 'push', 'role': 'provided',
                               'type': 'std_msgs/msg/String'}}}


def _generate(tmp_path: Path) -> Path:
    model = tmp_path / 'src' / 'robmosys.yaml'
    model.parent.mkdir(parents=True)
    model.write_text(yaml.safe_dump({'robmosys': 1, 'components': [
        _component('Numbers', 'numbers', 'python', ['python3-numpy']),
        _component('Solver', 'solver', 'cpp', ['eigen', 'yaml-cpp'])]}))
    result = load_workspace(find_model_files([tmp_path / 'src']),
                            fake_ament_index(tmp_path / 'prefix'))
    result.raise_errors()
    out = tmp_path / 'out'
    for package in ('numbers', 'solver'):
        plan = plan_package(result.workspace, package)
        create_missing_user_files(plan)
        generate_package(plan, out / package)
    return out


def _depends(package_xml: Path) -> list[str]:
    return [d.text or '' for d in ET.parse(package_xml).getroot().iter('depend')]


def test_system_depends_are_rosdep_keys_that_resolve(tmp_path):
    out = _generate(tmp_path)
    numbers, solver = _depends(out / 'numbers' / 'package.xml'), \
        _depends(out / 'solver' / 'package.xml')
    assert {'std_msgs', 'python3-numpy'} <= set(numbers)
    assert {'std_msgs', 'eigen', 'yaml-cpp'} <= set(solver)
    # keys, not packages: nothing of the build looks for them
    cmake = (out / 'solver' / 'CMakeLists.txt').read_text()
    assert 'find_package(std_msgs REQUIRED)' in cmake
    assert 'eigen' not in cmake and 'yaml-cpp' not in cmake

    # robmosys_runtime is a package of the workspace: its source is among the paths
    shutil.copytree(runtime_source(), out / 'robmosys_runtime')
    keys = {e.text or '' for path in out.glob('*/package.xml')
            for e in ET.parse(path).getroot() if e.tag.endswith('depend')}
    env = rosdep_env(tmp_path, keys, SYSTEM)
    rosdep(['update'], env)
    listed = rosdep(['keys', '--from-paths', str(out), '--ignore-src'], env).split()
    assert set(SYSTEM) <= set(listed), listed
    assert 'robmosys_runtime' not in listed
    simulated = rosdep(['install', '--simulate', '--reinstall', '--from-paths', str(out),
                        '--ignore-src', '-y', '--os=ubuntu:noble'], env)
    for system_package in SYSTEM.values():
        assert system_package in simulated, simulated
    assert 'ros-kilted-std-msgs' in simulated, simulated
