# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""A transition under way when SIGINT comes ends first; those asked after it are refused."""

import os
import signal
import subprocess
import sys
import threading

from conftest import wait_until
from lifecycle_msgs.msg import Transition
from lifecycle_msgs.srv import ChangeState
import rclpy
from robmosys_runtime.executors import EXECUTORS
from robmosys_runtime.system.lifecycle_calls import LifecycleCalls
from robmosys_runtime.transitions import TransitionGuard

#: a component's process whose activation takes a second; argv: its node's name,
#: its executor, or 'run' for what a generated component's own process runs. It
#: prints its node's state when it brings it down at the signal (run_nodes only).
SLOW_ACTIVATION = """
import sys
import time

from robmosys_runtime.main import run, run_nodes
from robmosys_runtime.node import ComponentNode


class Slow(ComponentNode):
    def on_activate(self, state):
        print('activating', flush=True)
        time.sleep(1.0)
        print('activated', flush=True)
        return super().on_activate(state)


def down(nodes):
    print('down', nodes[0]._state_machine.current_state[1], flush=True)


if sys.argv[2] == 'run':
    sys.exit(run(lambda: Slow(sys.argv[1])))
sys.exit(run_nodes([lambda: Slow(sys.argv[1])], executor_name=sys.argv[2], bring_down=down))
"""

#: the processes signalled: a process of a generated component, then each executor
WAYS = ('run', *EXECUTORS)


class _Output:
    """The lines a process prints, read in a thread."""

    def __init__(self, process: subprocess.Popen) -> None:
        self.lines = []
        self._thread = threading.Thread(target=self._read, args=(process,), daemon=True)
        self._thread.start()

    def _read(self, process: subprocess.Popen) -> None:
        for line in process.stdout:
            self.lines.append(line.rstrip())

    def shows(self, line: str, timeout: float = 20.0) -> bool:
        return wait_until(lambda: line in self.lines, timeout)

    def ended(self) -> list:
        self._thread.join(10)
        return self.lines


def _transition(client, label: str):
    request = ChangeState.Request()
    request.transition.id = getattr(Transition, f'TRANSITION_{label.upper()}')
    return client.call_async(request)


def _signalled_while_activating(spinning, executor: str):
    """SIGINT a process while it activates its node; return its exit code and output."""
    name = f'slow_{executor.replace("-", "_")}_{os.getpid()}'
    process = subprocess.Popen(
        [sys.executable, '-c', SLOW_ACTIVATION, name, executor],
        stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    try:
        output = _Output(process)
        node = spinning.add(rclpy.create_node(f'asking_{name}', context=spinning.context))
        # the calls of a manager: an answer rmw_fastrtps drops (to a client whose
        # reader of answers the service has not matched yet) is not a failure
        calls = LifecycleCalls(node, {name: f'/{name}'}, timeout=20, start_timeout=20,
                               timeouts={}, stop=threading.Event(), failed=lambda _: False)
        assert calls.change(name, Transition.TRANSITION_CONFIGURE) == 'inactive', output.lines
        _transition(calls.client(name, ChangeState, 'change_state'), 'activate')
        assert output.shows('activating'), output.lines
        process.send_signal(signal.SIGINT)
        code = process.wait(timeout=30)
        return code, output.ended()
    finally:
        if process.poll() is None:
            process.kill()
            process.wait()


def test_a_transition_under_way_at_sigint_ends_before_the_process_does(spinning):
    for executor in WAYS:
        code, lines = _signalled_while_activating(spinning, executor)
        assert code == 0, (executor, lines)
        # the activation was not cut short: rclpy logged no failure to publish its
        # event ('Failed to complete transition') or to start it
        assert 'activated' in lines, (executor, lines)
        assert executor == 'run' or 'down active' in lines, (executor, lines)
        assert not [line for line in lines if 'ERROR' in line or 'Traceback' in line], \
            (executor, lines)


def test_a_closed_guard_refuses_at_once_and_settles_with_the_transition_under_way():
    guard = TransitionGuard()
    context = rclpy.Context()
    rclpy.init(context=context)
    node = rclpy.create_node('guarded', context=context)
    started, release = threading.Event(), threading.Event()

    def change_state(request, response):
        started.set()
        release.wait(10)
        response.success = True
        return response
    try:
        answers = []
        under_way = threading.Thread(target=lambda: answers.append(guard.answer(
            node, change_state, None, ChangeState.Response())))
        under_way.start()
        assert started.wait(10)
        guard.close()
        assert not guard.answer(node, change_state, None, ChangeState.Response()).success
        assert not guard.settle(0.1)  # the transition under way holds it
        release.set()
        assert guard.settle(10)
        under_way.join(10)
        assert answers[0].success
    finally:
        release.set()
        node.destroy_node()
        rclpy.try_shutdown(context=context)
