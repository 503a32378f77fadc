# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""The send, query, action and event examples of test_workspace on real ROS 2.

All eight nodes of examples_system run together once for this module (started as
its launch.py would start them, configured and activated through their lifecycle
services); each test then checks what one pair did. The lifecycle test starts a
sender and a receiver of its own, since it drives them through every transition.
"""

from __future__ import annotations

import contextlib
from dataclasses import dataclass
import re
import signal
import subprocess
from typing import Iterator

import pytest

from colcon_robmosys.devtools.ros_env import Background, background, free_domain_id
from colcon_robmosys.devtools.system import LifecycleDriver, wait_until
from conftest import assert_no_traceback, BuiltWorkspace, requires_ros
from harness.launch_files import NodeLaunch, nodes_launch_file, read_launch_file

pytestmark = [pytest.mark.integration, requires_ros]

ACTIVATION_ORDER = ('receiver', 'sender', 'add_server', 'add_client', 'fibonacci_server',
                    'fibonacci_client', 'level_sensor', 'level_watcher')


def launched_nodes(built: BuiltWorkspace) -> dict[str, NodeLaunch]:
    """Return the nodes of examples_system's launch.py, by instance name."""
    share = built.share('examples_system')
    return {n.name: n for n in read_launch_file(nodes_launch_file(share), share)}


@dataclass
class Running:
    """The examples, running."""

    nodes: dict[str, NodeLaunch]
    processes: dict[str, Background]
    driver: LifecycleDriver

    def output(self, instance: str) -> str:
        return self.processes[instance].output()

    def wait_for(self, instance: str, pattern: str, count: int = 1,
                 timeout: float = 20.0) -> list:
        """Wait until the output of an instance matches a pattern count times."""
        regex = re.compile(pattern)
        wait_until(lambda: len(regex.findall(self.output(instance))) >= count, timeout)
        found = regex.findall(self.output(instance))
        assert len(found) >= count, self.output(instance)
        return found


@pytest.fixture(scope='module')
def examples(test_workspace_built) -> Iterator[Running]:
    nodes = launched_nodes(test_workspace_built)
    assert set(nodes) == set(ACTIVATION_ORDER)
    domain_id = free_domain_id()
    env = test_workspace_built.env(domain_id)
    install = test_workspace_built.install
    with contextlib.ExitStack() as stack:
        processes = {name: stack.enter_context(background(node.command(install), env=env))
                     for name, node in nodes.items()}
        driver = stack.enter_context(LifecycleDriver(domain_id))
        running = Running(nodes, processes, driver)
        # every node up and discovered before the first transition
        for name in ACTIVATION_ORDER:
            assert driver.state(nodes[name].fqn) == 'unconfigured'
        for name in ACTIVATION_ORDER:
            assert driver.transition(nodes[name].fqn, 'configure'), running.output(name)
        for name in ACTIVATION_ORDER:
            assert driver.transition(nodes[name].fqn, 'activate'), running.output(name)
        yield running
        for name in ACTIVATION_ORDER:
            assert_no_traceback(running.output(name))


def test_send_texts_arrive(examples):
    """The sender's texts reach the receiver, with the system's parameter values."""
    received = examples.wait_for('receiver', r'received hi there (\d+) value ([\d.]+)', 3)
    for seq, value in received:
        assert float(value) == pytest.approx(int(seq) * 0.5)


def test_query_blocking_and_callback_clients_get_answers(examples):
    blocking = examples.wait_for('add_client', r'blocking answer: (\d+) \+ 1000 = (\d+)', 3)
    assert all(int(total) == int(n) + 1000 for n, total in blocking)
    answers = examples.wait_for('add_client', r'callback answer: (\d+)', 3)
    # the asynchronous calls ask n + 2000 for the same n as the blocking ones
    assert {int(a) - 2000 for a in answers} <= {int(n) for n, _ in blocking} | {
        int(n) + 1 for n, _ in blocking}
    assert 'answering' in examples.output('add_server')


def test_action_goals_complete_with_feedback(examples):
    examples.wait_for('fibonacci_client', r'blocking result: \[0, 1, 1, 2, 3, 5\]', 2)
    examples.wait_for('fibonacci_client', r'callback result: \[0, 1, 1, 2, 3, 5, 8\]', 2)
    feedback = examples.wait_for('fibonacci_client', r'feedback: \[([\d, ]+)\]', 5)
    assert '0, 1, 1' in feedback
    assert '0, 1, 1, 2, 3, 5, 8' in feedback


def test_events_fire_only_when_their_condition_holds(examples):
    # threshold 16 (the system's value): levels 16..19 of each round of 0..19
    levels = examples.wait_for('level_watcher', r'event: level (\d+)', 8)
    assert {int(level) for level in levels} >= {16, 17, 18, 19}
    assert all(int(level) >= 16 for level in levels)
    notified = re.findall(r'level (\d+) notified to (\d+)', examples.output('level_sensor'))
    assert notified and all(int(level) >= 16 for level, _ in notified)
    # the single activation ended with its first event; the continuous one goes on
    examples.wait_for('level_watcher', r'single activation: 1 event\(s\), ended: True')
    assert not re.search(r'single activation: [2-9]\d* event', examples.output('level_watcher'))
    # deactivated after 12 events (max_events): no event of it comes any more
    examples.wait_for('level_watcher', r'continuous activation deactivated after 12 events')
    wait_until(lambda: False, 0.5)
    events = examples.output('level_watcher').count('event: level')
    notifications = examples.output('level_sensor').count('notified')
    wait_until(lambda: False, 1.5)
    assert examples.output('level_watcher').count('event: level') == events
    assert examples.output('level_sensor').count('notified') == notifications
    assert 'never activation: 0 event(s), ended: False' in examples.output('level_watcher')


def test_parameters_through_the_parameter_services(examples):
    sender = examples.nodes['sender'].fqn
    driver = examples.driver
    # the system's params.yaml overrides greeting (read-only) and scale; limit keeps its default
    assert driver.parameters(sender, ['greeting', 'scale', 'limit']) == {
        'greeting': 'hi there', 'scale': 0.5, 'limit': 100000}
    assert driver.parameters(examples.nodes['level_watcher'].fqn, ['threshold']) == {
        'threshold': 16}
    results = driver.set_parameters(sender, {'greeting': 'changed'})
    assert results['greeting'][0] is False
    assert 'read-only' in results['greeting'][1]
    results = driver.set_parameters(sender, {'scale': 10.5, 'limit': 0})
    assert [ok for ok, _ in results.values()] == [False, False]
    results = driver.set_parameters(sender, {'scale': 2.0})
    assert results['scale'][0] is True
    assert driver.parameters(sender, ['greeting', 'scale', 'limit']) == {
        'greeting': 'hi there', 'scale': 2.0, 'limit': 100000}
    examples.wait_for('receiver', r'received hi there (\d+) value \d+\.0\b', 1)


def test_ports_have_the_qos_of_the_model(examples):
    """The DDS endpoints, as discovery reports them, have the policies of the model."""
    from rclpy.qos import DurabilityPolicy, LivelinessPolicy, ReliabilityPolicy
    graph = examples.driver.node

    def endpoints(topic: str, kind: str) -> dict:
        found = graph.get_publishers_info_by_topic(topic) if kind == 'writer' \
            else graph.get_subscriptions_info_by_topic(topic)
        return {info.node_name: info.qos_profile for info in found}

    topic = '/examples/receiver/sText'
    assert wait_until(lambda: 'sender' in endpoints(topic, 'writer') and
                      'receiver' in endpoints(topic, 'reader'), 10)
    writer, reader = endpoints(topic, 'writer')['sender'], endpoints(topic, 'reader')['receiver']
    assert writer.reliability == reader.reliability == ReliabilityPolicy.RELIABLE
    assert writer.durability == reader.durability == DurabilityPolicy.VOLATILE
    assert writer.liveliness == reader.liveliness == LivelinessPolicy.AUTOMATIC
    assert (writer.deadline.nanoseconds, reader.deadline.nanoseconds) == (10**9, 2 * 10**9)
    assert writer.lifespan.nanoseconds == 10 * 10**9
    assert (writer.liveliness_lease_duration.nanoseconds,
            reader.liveliness_lease_duration.nanoseconds) == (3 * 10**9, 5 * 10**9)
    # the qos of an event port is that of its events: the sensor_data profile here
    feedback = '/examples/level_sensor/eLevel/_action/feedback'
    assert wait_until(lambda: 'level_watcher' in endpoints(feedback, 'reader'), 10)
    assert endpoints(feedback, 'reader')['level_watcher'].reliability == \
        ReliabilityPolicy.BEST_EFFORT
    assert endpoints(feedback, 'writer')['level_sensor'].reliability == \
        ReliabilityPolicy.RELIABLE


def test_inactive_servers_refuse_and_cleanup_ends_activations(examples):
    """Runs last: it takes the servers down."""
    driver, nodes = examples.driver, examples.nodes
    # an inactive query server answers with the default response, and says so
    assert driver.transition(nodes['add_server'].fqn, 'deactivate')
    examples.wait_for('add_server', r'request on qAdd while inactive')
    examples.wait_for('add_client', r'blocking answer: \d+ \+ 1000 = 0\b')
    # an inactive action server rejects goals
    assert driver.transition(nodes['fibonacci_server'].fqn, 'deactivate')
    examples.wait_for('fibonacci_client', r'no result: the goal was rejected')
    # cleanup of the event server aborts the activations it keeps, then releases the port
    sensor = nodes['level_sensor'].fqn
    goal_service = '/examples/level_sensor/eLevel/_action/send_goal'
    assert goal_service in driver.endpoints(sensor)['services']
    assert driver.transition(sensor, 'deactivate')
    assert driver.transition(sensor, 'cleanup')
    examples.wait_for('level_watcher', r'never activation: 0 event\(s\), ended: True')
    assert wait_until(lambda: goal_service not in driver.endpoints(sensor)['services'], 10)


def _count(regex: str, text: str) -> int:
    return len(re.findall(regex, text))


def test_lifecycle_of_a_sender_and_a_receiver(test_workspace_built):
    """Nothing runs unless active; timers stop and resume; cleanup releases the ports."""
    nodes = launched_nodes(test_workspace_built)
    domain_id = free_domain_id()
    env = {**test_workspace_built.env(domain_id), 'PYTHONFAULTHANDLER': '1'}
    install = test_workspace_built.install
    with contextlib.ExitStack() as stack:
        sender = stack.enter_context(background(nodes['sender'].command(install), env=env))
        receiver = stack.enter_context(background(nodes['receiver'].command(install), env=env))
        driver = stack.enter_context(LifecycleDriver(domain_id))
        s, r = nodes['sender'].fqn, nodes['receiver'].fqn
        topic = '/examples/receiver/sText'

        # a failing on_configure leaves the node unconfigured, with nothing created
        assert driver.set_parameters(r, {'fail_configure': True})['fail_configure'][0]
        assert not driver.transition(r, 'configure')
        assert driver.state(r) == 'unconfigured'
        assert 'fail_configure is set' in receiver.output()
        assert topic not in driver.endpoints(r)['subscriptions']
        assert driver.set_parameters(r, {'fail_configure': False})['fail_configure'][0]
        assert driver.transition(r, 'configure')

        # configured but inactive: the timer does not run, nothing is sent
        assert driver.transition(s, 'configure')
        assert wait_until(lambda: topic in driver.endpoints(s)['publishers'], 10)
        assert wait_until(lambda: topic in driver.endpoints(r)['subscriptions'], 10)
        wait_until(lambda: False, 1.0)
        assert 'sent' not in sender.output()

        assert driver.transition(r, 'activate')
        assert driver.transition(s, 'activate')
        assert wait_until(lambda: _count(r'received hi there', receiver.output()) >= 3, 10)

        # an inactive receiver runs no user code for what arrives
        assert driver.transition(r, 'deactivate')
        # a callback that had begun before the transition may still print: let it end
        wait_until(lambda: False, 0.5)
        received = _count(r'received hi there', receiver.output())
        sent = _count(r'sent \d+', sender.output())
        assert wait_until(lambda: _count(r'sent \d+', sender.output()) >= sent + 3, 5)
        assert _count(r'received hi there', receiver.output()) == received
        assert driver.transition(r, 'activate')

        # deactivated: the timer stops, nothing is published
        assert driver.transition(s, 'deactivate')
        wait_until(lambda: False, 0.5)
        sent = _count(r'sent \d+', sender.output())
        received = _count(r'received hi there', receiver.output())
        wait_until(lambda: False, 1.2)
        assert _count(r'sent \d+', sender.output()) == sent
        assert _count(r'received hi there', receiver.output()) == received

        # activated again: the timer resumes where it stopped
        assert driver.transition(s, 'activate')
        assert wait_until(lambda: _count(r'sent \d+', sender.output()) >= sent + 2, 5)
        numbers = [int(n) for n in re.findall(r'sent (\d+)', sender.output())]
        assert numbers == list(range(1, len(numbers) + 1))

        # cleanup releases the ports: the graph no longer shows them
        assert driver.transition(s, 'deactivate')
        assert driver.transition(s, 'cleanup')
        assert driver.state(s) == 'unconfigured'
        assert wait_until(lambda: topic not in driver.endpoints(s)['publishers'], 10)
        assert driver.transition(r, 'deactivate')
        assert driver.transition(r, 'cleanup')
        assert wait_until(lambda: topic not in driver.endpoints(r)['subscriptions'], 10)
        # and configure creates them again
        assert driver.transition(s, 'configure')
        assert wait_until(lambda: topic in driver.endpoints(s)['publishers'], 10)

        # SIGTERM and SIGINT end the nodes cleanly
        for process, signal_ in ((sender, signal.SIGTERM), (receiver, signal.SIGINT)):
            before = len(process.output())
            process.proc.send_signal(signal_)
            try:
                process.proc.wait(timeout=30)
            except subprocess.TimeoutExpired:
                # PYTHONFAULTHANDLER: SIGABRT prints where every thread is
                process.proc.send_signal(signal.SIGABRT)
                wait_until(lambda: process.proc.poll() is not None, 5)
                pytest.fail(f'{signal_.name} did not end the node:\n{process.output()}')
            assert process.proc.returncode == 0, process.output()
            assert_no_traceback(process.output()[before:], process.output())
