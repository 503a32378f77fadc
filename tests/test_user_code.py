# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""The user's implementation file survives generation and builds; the skeleton follows the model.

One small component on std_msgs (installed), so that no interface package is built.
"""

from __future__ import annotations

import contextlib
from pathlib import Path

import pytest

from colcon_robmosys.devtools.ros_env import background, loopback_env, workspace_env
from colcon_robmosys.devtools.system import LifecycleDriver, wait_until
from conftest import assert_no_traceback, colcon, requires_ros

pytestmark = [pytest.mark.integration, requires_ros]

MODEL = """\
robmosys: 1
components:
  - name: Echo
    package: echo
    language: python
    license: Apache-2.0
    maintainers: [{name: A, email: a@example.com}]
    ports:
      pOut: {pattern: push, role: provided, type: std_msgs/msg/String}
    activities:
      Tick: {period: 0.2, functions: [fTick]}
    functions:
      fTick:
        description: Publish a text.
"""

PLACEHOLDER = "        self.get_logger().warning('fTick is not implemented yet')\n"
MINE = "        self.pOut.publish(String(data='edited'))\n" \
    "        self.get_logger().info('my edit runs')\n"


def _ok(result) -> None:
    assert result.returncode == 0, result.stdout + result.stderr


def assert_echo_logs(install: Path, domain_id: int, text: str) -> None:
    """Run the installed Echo, bring it up, and wait for it to log text."""
    env = workspace_env(install, loopback_env(domain_id))
    with contextlib.ExitStack() as stack:
        node = stack.enter_context(background(
            [str(install / 'echo' / 'lib' / 'echo' / 'Echo')], env=env))
        driver = stack.enter_context(LifecycleDriver(domain_id))
        assert driver.transition('/Echo', 'configure')
        assert driver.transition('/Echo', 'activate')
        assert wait_until(lambda: text in node.output(), 10), node.output()


def test_user_code_survives_and_the_skeleton_follows_the_model(tmp_path, domain_id):
    model = tmp_path / 'src' / 'echo' / 'robmosys.yaml'
    model.parent.mkdir(parents=True)
    model.write_text(MODEL)
    impl = tmp_path / 'src' / 'echo' / 'src' / 'echo' / 'Echo_impl.py'

    _ok(colcon(['robmosys-generate'], cwd=tmp_path))
    created = impl.read_text()
    assert PLACEHOLDER in created
    impl.write_text(created.replace(PLACEHOLDER, MINE).replace(
        'from echo.Echo import Echo\n',
        'from echo.Echo import Echo\nfrom std_msgs.msg import String\n'))
    mine = impl.read_bytes()

    # generation never writes it again; build and rebuild use it as it is
    _ok(colcon(['build'], cwd=tmp_path))
    _ok(colcon(['robmosys-generate'], cwd=tmp_path))
    assert impl.read_bytes() == mine
    _ok(colcon(['build'], cwd=tmp_path))
    assert impl.read_bytes() == mine
    installed = list((tmp_path / 'install' / 'echo').rglob('echo/Echo_impl.py'))
    assert [p.read_bytes() for p in installed] == [mine]

    # and the node runs the user's code
    assert_echo_logs(tmp_path / 'install', domain_id, 'my edit runs')

    # the model gains a function: the skeleton shows it, the user's file is kept and
    # the build names what it lacks
    model.write_text(MODEL.replace('functions: [fTick]', 'functions: [fTick, fCount]') +
                     '      fCount:\n        description: Count the ticks.\n')
    _ok(colcon(['robmosys-generate'], cwd=tmp_path))
    assert impl.read_bytes() == mine
    result = colcon(['build'], cwd=tmp_path)
    assert result.returncode != 0
    output = result.stdout + result.stderr
    skeleton = tmp_path / 'build' / 'echo' / 'src-gen' / 'src-skel' / 'echo' / 'Echo_impl_skel.py'
    line = mine.decode().splitlines().index('class Echo_impl(Echo):') + 1
    assert f"{impl}:{line}:1: error: class 'Echo_impl' lacks the function 'fCount' of the " \
        'model; the skeleton src-skel/echo/Echo_impl_skel.py of the package shows what the ' \
        f'model asks for: {skeleton}' in output, output
    assert_no_traceback(output)
    assert impl.read_bytes() == mine
    text = skeleton.read_text()
    assert 'def fCount(self) -> None:' in text and 'Count the ticks.' in text
    assert 'def fTick(self) -> None:' in text

    # once the user adds it, the build passes again
    impl.write_text(mine.decode() + '\n    def fCount(self) -> None:\n'
                    '        """Count the ticks."""\n        self.ticks = 1\n')
    _ok(colcon(['build'], cwd=tmp_path))
    assert Path(skeleton).is_file()
