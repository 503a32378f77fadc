# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""
The smoke test of a system package: the system comes up, and every connection works.

Every system package has a test that ``colcon test`` runs and that calls
:func:`run`: it starts the system with its ``bringup`` executable (the system
manager), waits until the manager reports every managed instance active, then
checks within a timeout that each connection of the model carries data:

- a topic (push, send): a message arrives on it;
- a query: the service answers a request (a default one);
- an action or an event: its server is there. A goal would make the system
  do something (move a robot): a smoke test does not send one;

and that the manager's conformance watch finds no difference between the
running system and its model (``~/conformance``).

Finally it brings the system down with SIGINT, as an operator would, and
checks that the manager exits 0.
"""

from __future__ import annotations

import contextlib
import importlib
import json
import os
import signal
import subprocess
import sys
import tempfile
import threading
import time
from typing import Any, Callable, Dict, Iterator, List, Optional

from ament_index_python.packages import get_package_prefix, get_package_share_directory
import rclpy
from rclpy.executors import MultiThreadedExecutor
from rclpy.node import Node
from rclpy.qos import QoSProfile, ReliabilityPolicy
from robmosys_runtime.ports import ActionClient
from robmosys_runtime.tools.locations import resolve_locations
from std_srvs.srv import Trigger

#: compatible with every publisher: best effort and volatile are what any offer matches
_ANY_PUBLISHER = QoSProfile(depth=10, reliability=ReliabilityPolicy.BEST_EFFORT)


def interface(name: str) -> Any:
    """Return the Python class of an interface named ``pkg/kind/Type``."""
    package, kind, type_name = name.split('/')
    return getattr(importlib.import_module(f'{package}.{kind}'), type_name)


class Probe:
    """Listens to the topics of a system and calls its services and servers."""

    def __init__(self, node: Node) -> None:
        self._node = node
        self._received: Dict[str, int] = {}
        self._lock = threading.Lock()

    def listen(self, topic: str, msg_type: Any) -> None:
        """Count the messages on a topic, from now on."""
        def count(message: Any) -> None:
            with self._lock:
                self._received[topic] = self._received.get(topic, 0) + 1
        self._node.create_subscription(msg_type, topic, count, _ANY_PUBLISHER)

    def received(self, topic: str) -> int:
        """Return how many messages arrived on a topic (0: none, which is false)."""
        with self._lock:
            return self._received.get(topic, 0)

    def call(self, name: str, srv_type: Any, request: Any, timeout: float) -> Optional[Any]:
        """Call a service; return its answer, or None if none came within timeout."""
        client: Any = self._node.create_client(srv_type, name)
        try:
            deadline = time.monotonic() + timeout
            while time.monotonic() < deadline:
                if not client.wait_for_service(timeout_sec=min(1.0, timeout)):
                    continue
                answered = threading.Event()
                future = client.call_async(request)
                future.add_done_callback(lambda _: answered.set())
                # a request sent before the answer's way matched is lost: ask again
                if answered.wait(min(2.0, max(0.1, deadline - time.monotonic()))):
                    return future.result()
                client.remove_pending_request(future)
            return None
        finally:
            self._node.destroy_client(client)

    def server_there(self, name: str, action_type: Any, timeout: float) -> bool:
        """Tell whether an action server (or an event server) answers to a name."""
        client = ActionClient(self._node, action_type, name)
        try:
            return bool(client.wait_for_server(timeout_sec=timeout))
        finally:
            client.destroy()


#: the entities of a connection that is a topic: its messages can be counted
TOPIC_ENTITIES = ('publisher', 'subscription')


def _wait(condition: Callable[[], bool], timeout: float, period: float = 0.1) -> bool:
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        if condition():
            return True
        time.sleep(period)
    return condition()


def wait_until_up(probe: Probe, description: Dict[str, Any],
                  manager: 'subprocess.Popen[Any]', timeout: float) -> Optional[str]:
    """
    Wait until the manager reports every managed instance active.

    :param manager: the process of the system's ``bringup``
    :returns: None once the system is up; else why it did not come up (bringup
        ended, or the timeout passed: with the manager's last report)
    """
    package = description['package']
    answer: List[Any] = []

    def all_active() -> bool:
        if manager.poll() is not None:
            return True
        report = probe.call(f'/{package}_bringup/report', Trigger, Trigger.Request(), 5.0)
        answer[:] = [report]
        return report is not None and bool(report.success)
    if _wait(all_active, timeout, period=0.5) and manager.poll() is None:
        return None
    if manager.poll() is not None:
        return f'the system did not come up: bringup exited with code {manager.returncode}'
    managed = sum(1 for i in description['instances'] if i['managed'])
    last = answer[0].message if answer and answer[0] is not None else 'no report'
    return (f'the system did not come up within {timeout:g} s '
            f'({managed} managed instances):\n{last}')


def run(package: str, *, timeout: float = 30.0, bring_up_timeout: float = 120.0,
        bringup_args: Optional[List[str]] = None,
        description_file: Optional[str] = None) -> List[str]:
    """
    Run the smoke test of a system package; return its problems (none: it passed).

    :param timeout: seconds for every connection to carry data, once the system is up
    :param bring_up_timeout: seconds for every managed instance to become active
    :param bringup_args: further arguments of the bringup executable
    :param description_file: the system's description, by default the one the
        package installs (``share/<package>/bringup.json``)
    """
    if description_file is None:
        description_file = os.path.join(get_package_share_directory(package), 'bringup.json')
    with open(description_file, encoding='utf-8') as stream:
        description = resolve_locations(json.load(stream))
    bringup = os.path.join(get_package_prefix(package), 'lib', package, 'bringup')
    problems: List[str] = []
    with tempfile.TemporaryFile() as log:
        manager = subprocess.Popen(
            [sys.executable, bringup, '--exit-on-failure', '--description', description_file,
             *(bringup_args or [])],
            stdin=subprocess.DEVNULL, stdout=log, stderr=subprocess.STDOUT,
            start_new_session=True)
        try:
            with spinning_node(f'{package}_smoke_test') as node:
                problems += _check(node, description, manager, timeout, bring_up_timeout)
        finally:
            problems += stop(manager)
            if problems:
                log.seek(0)
                problems.append('what the system printed:\n' +
                                log.read().decode('utf-8', 'replace'))
    return problems


@contextlib.contextmanager
def spinning_node(name: str) -> Iterator[Node]:
    """Yield a node of a context of its own, spun in a thread, until the block ends."""
    context = rclpy.Context()
    rclpy.init(context=context)
    node = Node(name, context=context)
    executor = MultiThreadedExecutor(num_threads=4, context=context)
    executor.add_node(node)
    spinner = threading.Thread(target=executor.spin, daemon=True)
    spinner.start()
    try:
        yield node
    finally:
        executor.shutdown()
        # the spinning thread ends before the node and the context go
        spinner.join(10)
        node.destroy_node()
        rclpy.try_shutdown(context=context)


def _check(node: Node, description: Dict[str, Any], manager: 'subprocess.Popen[bytes]',
           timeout: float, bring_up_timeout: float) -> List[str]:
    package = description['package']
    probe = Probe(node)
    # a connection to a name outside the model: nothing runs at its other end here
    connections = [c for c in description.get('connections', []) if c['to']]
    for connection in connections:
        if connection['entity'] in TOPIC_ENTITIES:
            # listening before the system comes up: the first messages count too
            probe.listen(connection['name'], interface(connection['type']))
    not_up = wait_until_up(probe, description, manager, bring_up_timeout)
    if not_up:
        return [not_up]

    problems = []
    deadline = time.monotonic() + timeout
    for connection in connections:
        what = f"{connection['from']} -> {connection['to']} ({connection['name']}, " \
            f"{connection['type']})"
        left = max(1.0, deadline - time.monotonic())
        entity = connection['entity']
        if entity in TOPIC_ENTITIES:
            if not _wait(lambda: probe.received(connection['name']) > 0, left):
                problems.append(f'no message on {what} within {timeout:g} s')
        elif entity == 'service':
            srv_type = interface(connection['type'])
            if probe.call(connection['name'], srv_type, srv_type.Request(), left) is None:
                problems.append(f'no answer from {what} within {timeout:g} s')
        elif not probe.server_there(connection['name'], interface(connection['type']), left):
            problems.append(f'no server of {what} within {timeout:g} s')
    outside = [c['location'] for c in description.get('connections', []) if not c['to']]
    return problems + _conformance(probe, package, timeout, outside)


def _conformance(probe: Probe, package: str, timeout: float,
                 outside: List[str]) -> List[str]:
    """
    Return the differences the manager's watch finds between the system and its model.

    The watch checks the ports of an instance a few seconds after it became
    active: its answer is asked until it has none, or the timeout passed. That
    nothing is at the other end of a connection to a name outside the model
    (at one of the lines ``outside``) is no difference here: nothing runs
    there in a test.
    """
    differences: List[str] = []

    def conforms() -> bool:
        answer = probe.call(f'/{package}_bringup/conformance', Trigger, Trigger.Request(), 5.0)
        if answer is None:
            differences[:] = ['the system manager did not answer ~/conformance']
            return False
        differences[:] = [line for line in answer.message.splitlines() if line and not (
            any(line.startswith(f'{at}: ') for at in outside) and ' has no ' in line)]
        return not differences
    if _wait(conforms, timeout, period=1.0):
        return []
    return ['the running system differs from its model:\n' + '\n'.join(differences)]


def stop(manager: 'subprocess.Popen[Any]', timeout: float = 60.0) -> List[str]:
    """Bring the system down as an operator does (SIGINT); return the problems."""
    if manager.poll() is None:
        os.killpg(manager.pid, signal.SIGINT)
        try:
            manager.wait(timeout)
        except subprocess.TimeoutExpired:
            os.killpg(manager.pid, signal.SIGKILL)
            manager.wait()
            return [f'bringup did not end within {timeout:g} s of SIGINT']
        if manager.returncode != 0:
            return [f'bringup exited with code {manager.returncode} after SIGINT']
    return []
