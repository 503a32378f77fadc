# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""What README tells a newcomer works as written; docs hold no one's machine."""

from __future__ import annotations

import os
from pathlib import Path
import re
import shlex
import shutil
import subprocess
import sys

import pytest

from colcon_robmosys.devtools import ros_env
from conftest import REPO, requires_ros, TEST_WORKSPACE

#: Paths of a developer's machine or of a test run, which no reader has.
MACHINE_PATH = re.compile(r'(?<![\w.])/(?:work|home/\w+|root|tmp/pytest-\w+)/')


def _shell_block() -> list[str]:
    """Return the lines of README's block about one's own shell."""
    text = (REPO / 'README.md').read_text()
    block = re.search(r'in your own shell.*?```sh\n(.*?)```', text, re.DOTALL)
    assert block, 'README shows how to use the tools in your own shell'
    return [line.split('#')[0].strip() for line in block.group(1).splitlines()]


def _first_block() -> list[str]:
    """Return the commands of README's first block, without their comments."""
    block = re.search(r'```sh\n(.*?)```', (REPO / 'README.md').read_text(), re.DOTALL)
    assert block, 'README shows its commands in a sh block'
    return [line.split('#')[0].strip() for line in block.group(1).splitlines()
            if line.split('#')[0].strip()]


def _ci_make_commands() -> list[list[str]]:
    """Return the make commands .ci/run runs, in order, each as its words."""
    commands = []
    for line in (REPO / '.ci' / 'run').read_text().splitlines():
        code = line.split('#')[0]
        if code.lstrip().startswith('echo'):
            continue
        for command in re.findall(r'\bmake\b[^;&|}\n]*', code):
            commands.append(shlex.split(command))
    return commands


def test_readme_starts_with_the_two_commands():
    head = (REPO / 'README.md').read_text().split('\n## ')[0]
    assert _first_block() == ['make demo', 'make test']
    assert re.search(r'^make demo\b', head, re.MULTILINE)
    assert re.search(r'^make test\b', head, re.MULTILINE)


def test_ci_runs_the_commands_of_readme_on_each_distribution():
    """.ci/run runs README's first block as written, on Kilted and again on Jazzy."""
    lanes: dict[str, list[str]] = {}
    for words in _ci_make_commands():
        settings = dict(w.split('=', 1) for w in words[1:] if '=' in w)
        targets = [w for w in words[1:] if '=' not in w]
        # `make venv` first: both commands bootstrap it anyway, and one venv is built
        # at a time (they share setuptools' build folder of the tree)
        if targets == ['venv']:
            continue
        lanes.setdefault(settings.get('ROS_DISTRO', 'kilted'), []).append(
            ' '.join(['make', *targets]))
    assert lanes == {'kilted': _first_block(), 'jazzy': _first_block()}


@requires_ros
@pytest.mark.integration
def test_the_shell_lines_of_readme_build_a_workspace(tmp_path):
    """A fresh shell with README's source line builds an interface package."""
    source, build = _shell_block()[:2]
    assert source == 'source .venv/local_setup.bash'
    assert build.startswith('cd test_workspace && colcon build')
    shutil.copytree(TEST_WORKSPACE / 'src' / 'simple_msgs', tmp_path / 'src' / 'simple_msgs')
    # the venv of this test run stands where README's .venv does
    script = (f'{source.replace(".venv", shlex.quote(sys.prefix))} && '
              f'cd {shlex.quote(str(tmp_path))} && colcon build && '
              'source install/setup.bash && '
              'python3 -c "from simple_msgs.msg import OGM; print(OGM().width)"')
    # a newcomer's shell: no ROS variable, no venv on PATH
    env = {k: v for k, v in ros_env.loopback_env(ros_env.free_domain_id()).items()
           if not k.startswith(('AMENT_', 'CMAKE_', 'COLCON', 'VIRTUAL_ENV'))}
    env['PATH'] = os.pathsep.join(p for p in os.environ['PATH'].split(os.pathsep)
                                  if not p.startswith(sys.prefix))
    env['HOME'] = str(tmp_path)
    result = subprocess.run(['bash', '-c', script], env=env, capture_output=True, text=True,
                            timeout=600)
    assert result.returncode == 0, result.stdout + result.stderr
    assert result.stdout.splitlines()[-1] == '0'


@pytest.mark.parametrize('document', sorted(
    [REPO / 'README.md', *(REPO / 'docs').glob('*.md'), *(REPO / 'bench').glob('*.md'),
     *(REPO / 'tests' / 'golden').glob('*.md')]), ids=lambda p: p.name)
def test_documents_hold_no_machine_path(document: Path):
    found = [line for line in document.read_text().splitlines() if MACHINE_PATH.search(line)]
    assert found == []


#: what Jazzy's wheel list leaves out of Kilted's: packages Jazzy does not have, and
#: psutil, which Kilted's `fastdds` command imports (Jazzy's does not)
KILTED_ONLY = {'ros-ament-cmake-ros-core', 'psutil'}


def _requirements(name: str) -> list[str]:
    lines = (REPO / 'requirements' / name).read_text(encoding='utf-8').splitlines()
    return [re.split(r'[\[<>=]', line)[0] for line in lines if line and not line.startswith('#')]


def test_the_wheel_lists_of_the_distributions_agree():
    """`make venv ROS_DISTRO=jazzy` installs what the Kilted venv has, from ros-jazzy-*."""
    kilted = _requirements('ros.txt')
    jazzy = _requirements('ros-jazzy.txt')
    assert [name.replace('ros-', 'ros-jazzy-', 1) if name.startswith('ros-') else name
            for name in kilted if name not in KILTED_ONLY] == jazzy
