# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""rosdep without network.

rosdep 0.27 reads a local source (ROSDEP_SOURCE_PATH naming a list file with
`yaml file://<keys.yaml>`), a `file://` rosdistro index and a ROS_HOME of the
caller's own.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
import os
from pathlib import Path
import subprocess
import sys

import yaml

ROSDEP = Path(sys.prefix) / 'bin' / 'rosdep'


def rosdep_env(tmp_path: Path, keys: Iterable[str],
               system: Mapping[str, str] | None = None) -> dict[str, str]:
    """Return the environment of an offline rosdep that knows the keys.

    :param system: system keys -> the Ubuntu package each resolves to; every
      other key is a ROS package, resolved to its binary package
    """
    system = system or {}
    root = tmp_path / 'rosdep'
    (root / 'sources').mkdir(parents=True)
    # ROS packages resolve to their binary packages, as the rosdistro says
    rules = {key: {'ubuntu': [system.get(key, f"ros-kilted-{key.replace('_', '-')}")]}
             for key in keys}
    (root / 'keys.yaml').write_text(yaml.safe_dump(rules))
    (root / 'sources' / '10-local.list').write_text(f"yaml {(root / 'keys.yaml').as_uri()}\n")
    (root / 'distribution.yaml').write_text(yaml.safe_dump({
        'type': 'distribution', 'version': 2,
        'release_platforms': {'ubuntu': ['noble']}, 'repositories': {}}))
    (root / 'index-v4.yaml').write_text(yaml.safe_dump({
        'type': 'index', 'version': 4, 'distributions': {'kilted': {
            'distribution': ['distribution.yaml'], 'distribution_status': 'active',
            'distribution_type': 'ros2', 'python_version': 3}}}))
    # rosdep takes a package of a sourced prefix for a source package (which
    # --ignore-src skips): what resolves must not depend on what is sourced
    env = {k: v for k, v in os.environ.items()
           if k not in ('AMENT_PREFIX_PATH', 'ROS_PACKAGE_PATH', 'CMAKE_PREFIX_PATH')}
    env.update(ROSDEP_SOURCE_PATH=str(root / 'sources'),
               ROSDISTRO_INDEX_URL=(root / 'index-v4.yaml').as_uri(),
               ROS_HOME=str(root / 'home'), ROS_DISTRO='kilted', ROS_PYTHON_VERSION='3')
    return env


def rosdep(args: list[str], env: dict[str, str]) -> str:
    """Run rosdep, and return what it printed: it must succeed."""
    result = subprocess.run([str(ROSDEP), *args], env=env, capture_output=True, text=True,
                            timeout=120)
    assert result.returncode == 0, result.stdout + result.stderr
    return result.stdout
