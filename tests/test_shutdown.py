# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""A component ends quietly whatever it is doing when SIGINT or SIGTERM comes.

Each node of a pair of examples is signalled while it works: a periodic
activity publishing, an action goal sending feedback, an event server
notifying, a lifecycle transition under way. It must exit 0 with no traceback
and nothing logged as an error. A second signal ends it promptly and quietly.
"""

from __future__ import annotations

import contextlib
import re
import signal
import subprocess
import time
from typing import Iterator

import pytest

from colcon_robmosys.devtools.ros_env import Background, background, free_domain_id
from colcon_robmosys.devtools.system import LifecycleDriver, wait_until
from conftest import assert_no_traceback, BuiltWorkspace, requires_ros
from harness.launch_files import nodes_launch_file, read_launch_file

pytestmark = [pytest.mark.integration, requires_ros]

#: what a quiet shutdown never prints
NOISE = re.compile(r'Traceback|never retrieved|\[ERROR\]|Exception|failed')
#: seconds in which a second signal is the same request (robmosys_runtime.main.SAME_REQUEST)
SAME_REQUEST = 1.0

#: (the node signalled, its peer, what the node prints while it works)
PAIRS = {
    'periodic publisher': ('sender', 'receiver', r'sent \d+'),
    'action goal with feedback': ('fibonacci_server', 'fibonacci_client', r'feedback'),
    'action client waiting': ('fibonacci_client', 'fibonacci_server', r'feedback'),
    'event server notifying': ('level_sensor', 'level_watcher', r'notified to'),
}


@contextlib.contextmanager
def _running(built: BuiltWorkspace, names: tuple[str, ...],
             activate: bool = True) -> Iterator[tuple[dict[str, Background], LifecycleDriver,
                                                      dict]]:
    share = built.share('examples_system')
    nodes = {n.name: n for n in read_launch_file(nodes_launch_file(share), share)}
    domain_id = free_domain_id()
    env = built.env(domain_id)
    with contextlib.ExitStack() as stack:
        processes = {name: stack.enter_context(
            background(nodes[name].command(built.install), env=env)) for name in names}
        driver = stack.enter_context(LifecycleDriver(domain_id))
        for name in names:
            assert driver.state(nodes[name].fqn) == 'unconfigured'
        if activate:
            for label in ('configure', 'activate'):
                for name in names:
                    try:
                        done = driver.transition(nodes[name].fqn, label)
                    except TimeoutError as error:
                        pytest.fail(f'{name}: {label}: {error}:\n{processes[name].output()}')
                    assert done, processes[name].output()
        yield processes, driver, nodes


def _stop(process: Background, signum: int, timeout: float = 15.0) -> tuple[int, str]:
    """Signal the process; return its exit code and what it printed after the signal.

    What came before is not judged: a service answer the node could not send
    while DDS had matched only one direction of the service (rmw_fastrtps's
    'failed to send response (timeout)' warning, which the driver's retry
    makes good) is not part of its shutdown.
    """
    before = len(process.output())
    process.proc.send_signal(signum)
    try:
        code = process.proc.wait(timeout=timeout)
    except subprocess.TimeoutExpired:
        pytest.fail(f'no exit {timeout} s after {signal.Signals(signum).name}:\n'
                    f'{process.output()}')
    return code, process.output()[before:]


#: the moments within the work at which a signal comes: SIGINT finds the node at
#: several places; SIGTERM takes the same path (one handler ends the node on either)
MOMENTS = {signal.SIGINT: (0.0, 0.037, 0.11), signal.SIGTERM: (0.037,)}


@pytest.mark.parametrize('signum', [signal.SIGINT, signal.SIGTERM], ids=['SIGINT', 'SIGTERM'])
@pytest.mark.parametrize('case', sorted(PAIRS))
def test_a_signal_while_working_ends_the_node_quietly(test_workspace_built, case, signum):
    name, peer, working = PAIRS[case]
    for delay in MOMENTS[signum]:
        with _running(test_workspace_built, (name, peer)) as (processes, _, _):
            node = processes[name]
            assert wait_until(lambda: re.search(working, node.output() +
                                                processes[peer].output()), 20), \
                node.output() + processes[peer].output()
            time.sleep(delay)
            code, after = _stop(node, signum)
            assert code == 0, node.output()
            assert not NOISE.search(after), node.output()


def test_a_signal_during_a_transition_ends_the_node_quietly(test_workspace_built):
    running = _running(test_workspace_built, ('sender',), activate=False)
    with running as (processes, driver, nodes):
        sender = processes['sender']
        fqn = nodes['sender'].fqn
        assert driver.transition(fqn, 'configure')
        # activate, and the signal comes while the node goes through it
        driver.request_transition(fqn, 'activate')
        code, after = _stop(sender, signal.SIGINT)
        assert code == 0, sender.output()
        assert not NOISE.search(after), sender.output()


def test_a_second_signal_ends_the_node_promptly_and_quietly(test_workspace_built):
    name, peer, working = PAIRS['action goal with feedback']
    with _running(test_workspace_built, (name, peer)) as (processes, _, _):
        node = processes[name]
        assert wait_until(lambda: re.search(working, processes[peer].output()), 20)
        node.proc.send_signal(signal.SIGINT)
        # a second one at once is the same request (a terminal's and ros2 launch's):
        # the user's second Ctrl-C comes later
        time.sleep(SAME_REQUEST + 0.2)
        if node.proc.poll() is None:
            node.proc.send_signal(signal.SIGINT)
        started = time.monotonic()
        node.proc.wait(timeout=10)
        assert time.monotonic() - started < 5
        assert_no_traceback(node.output())
