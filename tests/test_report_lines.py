# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""A difference names the model file the user wrote, at its line, on real rclpy.

handwritten_system's echo relays what arrives on ``/outside/words``, a name outside
the model that nothing publishes on: its manager's conformance watch and ``bringup
--check`` report it at the connection's line. Run from the workspace, they name
``src/handwritten_system/robmosys.yaml`` (the file the user wrote, below the current
folder: shown relative to it); from an install copied elsewhere, where that file is
not, the installed copy, whose lines are the same.
"""

from __future__ import annotations

import re
import shutil
import subprocess
import sys

import pytest

from colcon_robmosys.devtools import ros_env
from colcon_robmosys.devtools.ros_env import background
from colcon_robmosys.devtools.system import wait_until
from conftest import requires_ros

pytestmark = [pytest.mark.integration, requires_ros]

SYSTEM = 'handwritten_system'
#: the connection the watch reports, as the model states it
CONNECTION = '{to: echo.rIn, topic: /outside/words}'
MESSAGE = 'error: /outside/words has no publisher'


def test_a_difference_names_the_users_model_file_at_its_line(
        test_workspace_built, domain_id, tmp_path):
    built = test_workspace_built
    source = built.root / 'src' / SYSTEM / 'robmosys.yaml'
    line = next(n for n, text in enumerate(source.read_text().splitlines(), 1)
                if CONNECTION in text)
    column = source.read_text().splitlines()[line - 1].index('{') + 1
    where = f'src/{SYSTEM}/robmosys.yaml:{line}:{column}'
    env = built.env(domain_id)
    bringup = built.install / SYSTEM / 'lib' / SYSTEM / 'bringup'
    with background([sys.executable, str(bringup), '--check-period', '0.5'], env=env,
                    cwd=built.root, stop_timeout=30) as manager:
        # the watch's line, at the user's file
        assert wait_until(lambda: f'bringup: {where}: difference: /outside/words has no '
                          'publisher' in manager.output(), timeout=120), manager.output()
        # the one-shot check, from the workspace too
        check = subprocess.run([sys.executable, str(bringup), '--check'], env=env,
                               cwd=built.root, capture_output=True, text=True, timeout=60)
        assert check.returncode == 1, check.stdout + check.stderr
        assert f'{where}: {MESSAGE}' in check.stdout.splitlines(), check.stdout

        # the install copied elsewhere (a robot's): the model file is not there; the
        # installed copy is named, at the same line
        moved = tmp_path / 'robot' / 'install'
        shutil.copytree(built.install, moved, symlinks=True)
        moved_env = ros_env.workspace_env(moved, ros_env.loopback_env(domain_id))
        copy = moved / SYSTEM / 'share' / SYSTEM / 'robmosys' / 'robmosys.yaml'
        assert CONNECTION in copy.read_text().splitlines()[line - 1]
        check = subprocess.run(
            [sys.executable, str(moved / SYSTEM / 'lib' / SYSTEM / 'bringup'), '--check'],
            env=moved_env, cwd=tmp_path, capture_output=True, text=True, timeout=60)
        assert check.returncode == 1, check.stdout + check.stderr
        shown = copy.relative_to(tmp_path)
        assert f'{shown}:{line}:{column}: {MESSAGE}' in check.stdout.splitlines(), \
            check.stdout
        assert not re.search(r'src/\w+/robmosys\.yaml', check.stdout), check.stdout
