# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""What a system's start refuses before anything starts, on the installed fleet_system.

``bringup --params-file FILE`` checks the operator's file as ``check_params`` does: each
mistake is a line at its place in the file, nothing is started, exit 2. The launch
files' ``params_file`` runs the same check (``robmosys_runtime.tools.paramcheck.
check_operator_file``, called here as the launch files call it: launch is not on
PyPI, tests/test_launch_ros.py runs the launch files where it is installed). Every
numeric option of bringup refuses a value out of its range the same way.
"""

from __future__ import annotations

import subprocess
import sys
import time

import pytest

from colcon_robmosys.devtools.ros_env import background, free_domain_id
from conftest import assert_no_traceback, BuiltWorkspace, requires_ros

pytestmark = [pytest.mark.integration, requires_ros]

SYSTEM = 'fleet_system'

#: a wrong type, an unknown parameter with a near name, a value out of rcl's reading
BROKEN = """\
/**:
  ros__parameters:
    use_sim_time: true
/robot1/*:
  ros__parameters:
    noOfScans: three
robot2:
  publisher:
    ros__parameters:
      indor: true
      indoor: 'yes'
"""
#: what check_params says of it: the lines bringup and the launch files print
BROKEN_LINES = [
    "site.yaml:6:16: error: parameter 'noOfScans' of /robot1/publisher: 'three' is read "
    'as a string, the parameter is an int',
    "site.yaml:10:7: error: node /robot2/publisher has no parameter 'indor'; did you mean "
    "'indoor'? (its parameters: indoor, noOfScans, use_sim_time)",
    "site.yaml:11:15: error: parameter 'indoor' of /robot2/publisher: 'yes' is read as a "
    'string, the parameter is a bool']


def _bringup_command(built: BuiltWorkspace, *args: str) -> list[str]:
    return [sys.executable, str(built.install / SYSTEM / 'lib' / SYSTEM / 'bringup'), *args]


def _refused(built: BuiltWorkspace, cwd, *args: str) -> tuple[int, str]:
    """
    Run bringup; return its exit status and output once it ended, asserting nothing started.

    Every process of the run carries a marker in its environment; any other than
    bringup's own, seen while it ran, is a process of the system it started.
    """
    from test_process_layout import marked_env, MARKER, processes_marked
    env = marked_env(built, free_domain_id())
    started: set[int] = set()
    with background(_bringup_command(built, *args), env=env, cwd=cwd,
                    stop_timeout=30) as bringup:
        deadline = time.monotonic() + 60
        while bringup.proc.poll() is None and time.monotonic() < deadline:
            started |= set(processes_marked(env[MARKER])) - {bringup.proc.pid}
            time.sleep(0.01)
        started |= set(processes_marked(env[MARKER])) - {bringup.proc.pid}
        status = bringup.proc.poll()
        output = bringup.output()
    assert status is not None, f'bringup {" ".join(args)} did not end within 60 s:\n{output}'
    assert not started, f'bringup started processes {sorted(started)}:\n{output}'
    assert_no_traceback(output)
    return status, output


def test_bringup_refuses_a_broken_operators_file_at_its_lines(test_workspace_built, tmp_path):
    (tmp_path / 'site.yaml').write_text(BROKEN)
    status, output = _refused(test_workspace_built, tmp_path, '--params-file', 'site.yaml')
    assert status == 2, output
    assert output.splitlines() == BROKEN_LINES + [
        "bringup: error: --params-file 'site.yaml' does not fit the system fleet_system "
        '(3 errors); nothing was started'], output


def test_bringup_refuses_an_operators_file_that_is_not_utf8(test_workspace_built, tmp_path):
    (tmp_path / 'site.yaml').write_bytes(
        b'/robot1/publisher:\n  ros__parameters:\n    frame: caf\xe9\n')
    status, output = _refused(test_workspace_built, tmp_path, '--params-file', 'site.yaml')
    assert status == 2, output
    assert output.splitlines() == [
        'site.yaml:3:15: error: not a text in UTF-8 (byte 0xe9)',
        "bringup: error: --params-file 'site.yaml' does not fit the system fleet_system "
        '(1 error); nothing was started'], output


def test_the_launch_files_check_the_operators_file_as_bringup_does(
        test_workspace_built, tmp_path):
    """The function SystemArguments' check calls, on the installed system's description."""
    (tmp_path / 'site.yaml').write_text(BROKEN)
    (tmp_path / 'good.yaml').write_text('/robot1/publisher:\n  ros__parameters:\n'
                                        '    noOfScans: 4\n')
    script = """
import json, sys
from robmosys_runtime.tools.arguments import ArgumentError
from robmosys_runtime.tools.paramcheck import check_operator_file
with open(sys.argv[1], encoding='utf-8') as stream:
    description = json.load(stream)
for path in sys.argv[2:]:
    try:
        print('fits:', check_operator_file(description, path))
    except ArgumentError as error:
        print('refused:', error)
        print(*error.lines, sep='\\n')
"""
    description = test_workspace_built.share(SYSTEM) / 'bringup.json'
    result = subprocess.run(
        [sys.executable, '-c', script, str(description), 'good.yaml', 'site.yaml'],
        env=test_workspace_built.env(free_domain_id()), cwd=tmp_path, capture_output=True,
        text=True, timeout=60)
    assert result.returncode == 0, result.stdout + result.stderr
    assert result.stdout.splitlines() == [
        'fits: []',
        "refused: params_file 'site.yaml' does not fit the system fleet_system (3 errors)",
        *BROKEN_LINES], result.stdout


@pytest.mark.parametrize('option, value, why', [
    ('--timeout', '0', 'is not above 0'),
    ('--start-timeout', '-5', 'is not above 0'),
    ('--heartbeat', '-1', 'is below 0 (0: off)'),
    ('--respawn-delay', 'nan', 'is not a number'),
    ('--diagnostics-period', '0', 'is not above 0'),
    ('--check-period', '-1', 'is below 0 (0: off)'),
    ('--check-period', 'inf', 'is too large (at most 1e9)'),
    ('--silence', '0', 'is not above 0'),
    ('--check-wait', '-0.5', 'is below 0'),
    ('--timeout', 'soon', 'is not a number'),
])
def test_bringup_refuses_an_option_out_of_its_range(
        test_workspace_built, tmp_path, option, value, why):
    status, output = _refused(test_workspace_built, tmp_path, option, value)
    assert status == 2, output
    assert output.splitlines() == [
        f'bringup: error: {option} {value}: {why}; nothing was started'], output
