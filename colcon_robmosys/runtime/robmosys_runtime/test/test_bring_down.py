# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""A process that brings its nodes down itself at SIGINT (run_nodes' bring_down), for real."""

import signal
import subprocess
import sys
import time

from robmosys_runtime.executors import EXECUTORS
from robmosys_runtime.main import ENDING_REPORT, SAME_REQUEST

#: a process of one lifecycle node that brings itself down at SIGINT (run_nodes'
#: bring_down), as the shared process of bringup does; argv: executor, how long
#: the bring-down takes, whether a timer fails
BRINGS_ITSELF_DOWN = """
import sys
import time

from rclpy.lifecycle import LifecycleNode
from robmosys_runtime.main import run_nodes


class Journaled(LifecycleNode):
    def on_deactivate(self, state):
        print('on_deactivate', flush=True)
        return super().on_deactivate(state)

    def on_cleanup(self, state):
        print('on_cleanup', flush=True)
        return super().on_cleanup(state)

    def destroy_node(self):
        if sys.argv[3] == 'hang':
            hangs_being_destroyed()
        super().destroy_node()


def hangs_being_destroyed():
    time.sleep(60)


def up(nodes):
    nodes[0].trigger_configure()
    nodes[0].trigger_activate()
    if sys.argv[3] == 'fail':
        nodes[0].create_timer(0.3, lambda: 1 / 0)
    print('up', flush=True)


def down(nodes):
    time.sleep(float(sys.argv[2]))
    # the context is up still: a transition publishes its event as from a service
    print('context', nodes[0].context.ok(), flush=True)
    nodes[0].trigger_deactivate()
    nodes[0].trigger_cleanup()
    print('down', nodes[0]._state_machine.current_state[1], flush=True)


sys.exit(run_nodes([lambda: Journaled('journaled')], executor_name=sys.argv[1],
                   before_spin=up, bring_down=down))
"""


def _bringing_itself_down(executor, takes=0.0, fail=False, hang=False):
    process = subprocess.Popen(
        [sys.executable, '-c', BRINGS_ITSELF_DOWN, executor, str(takes),
         'fail' if fail else 'hang' if hang else 'ok'], stdout=subprocess.PIPE,
        stderr=subprocess.STDOUT, text=True)
    lines = []
    for line in process.stdout:
        lines.append(line.rstrip())
        if line.startswith('up'):
            break
    return process, lines


def _ended(process, lines, timeout=30):
    try:
        output, _ = process.communicate(timeout=timeout)
    except subprocess.TimeoutExpired:
        process.kill()
        output, _ = process.communicate()
        raise AssertionError('\n'.join(lines) + output)
    return process.returncode, lines + output.splitlines()


def test_a_process_brings_its_nodes_down_at_sigint_on_each_executor():
    for executor in EXECUTORS:
        process, lines = _bringing_itself_down(executor)
        # a terminal's Ctrl-C and ros2 launch's SIGINT: one request, come twice
        process.send_signal(signal.SIGINT)
        process.send_signal(signal.SIGINT)
        code, lines = _ended(process, lines)
        assert code == 0, (executor, lines)
        assert [line for line in lines if line != 'up'] == [
            'context True', 'on_deactivate', 'on_cleanup', 'down unconfigured'], \
            (executor, lines)


def test_a_later_second_signal_ends_a_bring_down_that_hangs_at_once():
    process, lines = _bringing_itself_down('multi-threaded', takes=60.0)
    process.send_signal(signal.SIGTERM)
    time.sleep(SAME_REQUEST + 0.5)
    process.send_signal(signal.SIGINT)
    start = time.monotonic()
    code, lines = _ended(process, lines, timeout=10)
    assert code == 128 + signal.SIGINT and time.monotonic() - start < 5, lines
    assert 'on_deactivate' not in lines


def test_a_callback_that_fails_ends_the_process_bringing_nothing_down():
    process, lines = _bringing_itself_down('multi-threaded', fail=True)
    code, lines = _ended(process, lines)
    assert code != 0, lines
    assert 'ZeroDivisionError: division by zero' in lines, lines
    assert 'on_deactivate' not in lines


def test_a_process_still_ending_after_its_context_says_where_its_threads_are():
    # what a process that hangs on its way out prints, before whoever asked
    # it to end kills it: the stack of each of its threads, the hang named
    process, lines = _bringing_itself_down('single-threaded', hang=True)
    try:
        process.send_signal(signal.SIGINT)
        start = time.monotonic()
        for line in process.stdout:
            lines.append(line.rstrip())
            if 'in hangs_being_destroyed' in line:
                break
        waited = time.monotonic() - start
        assert any('in hangs_being_destroyed' in line for line in lines), lines
        assert ENDING_REPORT - 0.5 < waited < ENDING_REPORT + 10, (waited, '\n'.join(lines))
        # it goes on hanging: the report does not end it
        assert process.poll() is None
    finally:
        process.kill()
        process.communicate()
