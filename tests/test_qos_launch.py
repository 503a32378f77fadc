# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""QoS at launch time, on real rclpy: ROS 2's own qos_overrides parameters.

A generated Python component run with a parameter file of qos_overrides has
the QoS the file gives, as the ROS graph shows it to another node; so has an
instance whose system model overrides the QoS of its ports (cfg/params.yaml,
run by the system's bringup). The overrides are read-only parameters declared
when a port is created, on configure: a configure after a cleanup finds them
declared and keeps them.
"""

from __future__ import annotations

import sys
import time
from typing import Any, Iterator

import pytest
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from std_msgs.msg import String
from test_cpp_system import requires_rclcpp

from colcon_robmosys.devtools.ros_env import Background, background
from colcon_robmosys.devtools.system import LifecycleDriver, wait_until
from conftest import assert_no_traceback, build_workspace, BuiltWorkspace, requires_ros

pytestmark = [pytest.mark.integration, requires_ros]

MODEL = """\
robmosys: 1
defaults:
  license: Apache-2.0
  maintainers: [{name: A, email: a@example.com}]
components:
  - name: Talker
    package: qos_talker
    language: python
    ports:
      pChat: {pattern: push, role: provided, type: std_msgs/msg/String, qos: {depth: 2}}
    activities:
      Talk: {period: 0.1, functions: [fTalk]}
    functions:
      fTalk:
        code: |
          self.count = getattr(self, 'count', 0) + 1
          self.pChat.publish(String(data=f'hi {self.count}'))
  - name: Listener
    package: qos_listener
    language: LANGUAGE
    ports:
      rChat: {pattern: push, role: required, type: std_msgs/msg/String}
    activities:
      Hear: {trigger: rChat, functions: [fHear]}
    functions:
      fHear:
        code: |
          HEAR
systems:
  - package: qos_system
    instances:
      talker:
        component: qos_talker
        namespace: qos
        qos: {pChat: {reliability: best_effort, durability: transient_local, lifespan: 3}}
      listener:
        component: qos_listener
        namespace: qos
        qos: {rChat: {reliability: best_effort, depth: 3}}
    connections:
      - {from: talker.pChat, to: listener.rChat}
"""

#: What an operator writes: the nested form of the ROS 2 documentation.
OPERATOR_PARAMS = """\
/solo/talker:
  ros__parameters:
    qos_overrides:
      /solo/pChat:
        publisher:
          durability: transient_local
          depth: 7
          deadline: 2000000000
"""


#: The listener's function, per language.
HEAR = {'python': "self.get_logger().info(f'heard {commobj.data}')",
        'cpp': 'RCLCPP_INFO(get_logger(), "heard %s", commobj.data.c_str());'}


@pytest.fixture(scope='module', params=[
    'python', pytest.param('cpp', marks=requires_rclcpp)])
def language(request) -> str:
    """Return the language of the listener."""
    return request.param


@pytest.fixture(scope='module')
def built(language, tmp_path_factory) -> BuiltWorkspace:
    """Return the model built, its listener in Python or in C++."""
    src = tmp_path_factory.mktemp('qos_src')
    (src / 'qos').mkdir()
    (src / 'qos' / 'robmosys.yaml').write_text(
        MODEL.replace('LANGUAGE', language).replace('HEAR', HEAR[language]))
    return build_workspace(src, tmp_path_factory.mktemp('qos_ws'))


def _endpoint(driver: LifecycleDriver, topic: str, kind: str, timeout: float = 20.0):
    """Return the QoS of the one publisher or subscription of a topic, once it shows."""
    query = (driver.node.get_publishers_info_by_topic if kind == 'publisher'
             else driver.node.get_subscriptions_info_by_topic)
    found: list = []

    def seen() -> bool:
        # neither the driver nor a system manager, whose conformance watch takes the
        # latest message of each push port it watches (a reader on its node
        # <system>_bringup_watch)
        found[:] = [i for i in query(topic) if i.node_name != driver.node.get_name() and
                    not i.node_name.endswith(('_bringup', '_bringup_watch'))]
        return len(found) == 1
    assert wait_until(seen, timeout=timeout), f'{kind} of {topic}: {found}'
    return found[0].qos_profile


def _configure_twice(driver: LifecycleDriver, node: Background, fqn: str, topic: str,
                     kind: str) -> Iterator[Any]:
    """Configure, clean up and configure a node again; yield its port's QoS each time."""
    query = (driver.node.get_publishers_info_by_topic if kind == 'publisher'
             else driver.node.get_subscriptions_info_by_topic)
    for step in ('configure', 'cleanup', 'configure'):
        assert driver.transition(fqn, step), (step, node.output())
        if step == 'cleanup':
            # the port is gone; its parameters stay declared, and are found so
            assert wait_until(lambda: not query(topic), timeout=20), node.output()
        else:
            yield _endpoint(driver, topic, kind)


def test_a_parameter_file_overrides_the_qos_of_a_component(built, language, domain_id,
                                                           tmp_path):
    if language != 'python':
        pytest.skip('the talker, in Python, is the same in both builds')
    params = tmp_path / 'operator.yaml'
    params.write_text(OPERATOR_PARAMS)
    executable = built.install / 'qos_talker' / 'lib' / 'qos_talker' / 'Talker'
    command = [sys.executable, str(executable), '--ros-args', '-r', '__ns:=/solo',
               '-r', '__node:=talker', '--params-file', str(params)]
    with background(command, env=built.env(domain_id)) as talker, \
            LifecycleDriver(domain_id) as driver:
        for qos in _configure_twice(driver, talker, '/solo/talker', '/solo/pChat', 'publisher'):
            # the file's durability and deadline, the model's reliability
            assert (qos.durability, qos.deadline.nanoseconds, qos.reliability) == (
                DurabilityPolicy.TRANSIENT_LOCAL, 2_000_000_000, ReliabilityPolicy.RELIABLE)
        assert driver.transition('/solo/talker', 'activate'), talker.output()
        names = [f'qos_overrides./solo/pChat.publisher.{p}'
                 for p in ('depth', 'history', 'reliability', 'lifespan')]
        values = driver.parameters('/solo/talker', names)
        # the file's depth, the model's history, every policy declared
        assert [values[n] for n in names[:3]] == [7, 'keep_last', 'reliable']
        assert isinstance(values[names[3]], int)
        # the depth at work: stopped after some 20 messages, the transient-local
        # publisher hands a subscriber that comes late the last 7 it kept (the
        # file's depth), not the model's 2
        time.sleep(2)
        assert driver.transition('/solo/talker', 'deactivate'), talker.output()
        received: list[str] = []
        driver.node.create_subscription(
            String, '/solo/pChat', lambda m: received.append(m.data),
            QoSProfile(depth=100, durability=DurabilityPolicy.TRANSIENT_LOCAL))
        assert wait_until(lambda: driver.spin(0.05) or len(received) >= 7, timeout=20), \
            received
        deadline = time.monotonic() + 1
        while time.monotonic() < deadline:
            driver.spin(0.05)
        last = [int(m.split()[1]) for m in received]
        assert last == list(range(last[0], last[0] + 7)) and last[0] > 7, received
        assert_no_traceback(talker.output())


def test_the_qos_a_system_gives_an_instance_is_the_running_node_s(built, domain_id):
    params = (built.share('qos_system') / 'cfg' / 'params.yaml').read_text()
    assert 'qos_overrides./qos/talker/pChat.publisher.reliability: "best_effort"' in params
    bringup = built.install / 'qos_system' / 'lib' / 'qos_system' / 'bringup'
    with background([sys.executable, str(bringup)], env=built.env(domain_id),
                    stop_timeout=30) as system, LifecycleDriver(domain_id) as driver:
        assert wait_until(lambda: 'bringup: 2 of 2 managed instances active' in
                          system.output(), timeout=90), system.output()
        writer = _endpoint(driver, '/qos/talker/pChat', 'publisher')
        assert (writer.reliability, writer.durability) == (
            ReliabilityPolicy.BEST_EFFORT, DurabilityPolicy.TRANSIENT_LOCAL)
        assert writer.lifespan.nanoseconds == 3_000_000_000
        reader = _endpoint(driver, '/qos/talker/pChat', 'subscription')
        assert (reader.reliability, reader.durability) == (
            ReliabilityPolicy.BEST_EFFORT, DurabilityPolicy.VOLATILE)
        assert driver.parameters('/qos/listener', [
            'qos_overrides./qos/talker/pChat.subscription.depth']) == {
            'qos_overrides./qos/talker/pChat.subscription.depth': 3}
        # and the two still talk
        assert wait_until(lambda: 'heard hi' in system.output(), timeout=30), system.output()


def test_a_parameter_file_overrides_the_qos_of_a_cpp_component(built, language, domain_id,
                                                               tmp_path):
    if language != 'cpp':
        pytest.skip('the listener is in Python in this build')
    params = tmp_path / 'operator.yaml'
    params.write_text("""\
/solo/listener:
  ros__parameters:
    qos_overrides./solo/rChat.subscription.durability: transient_local
    qos_overrides./solo/rChat.subscription.liveliness_lease_duration: 4000000000
""")
    command = [str(built.install / 'qos_listener' / 'lib' / 'qos_listener' / 'Listener'),
               '--ros-args', '-r', '__ns:=/solo', '-r', '__node:=listener',
               '--params-file', str(params)]
    with background(command, env=built.env(domain_id)) as listener, \
            LifecycleDriver(domain_id) as driver:
        for qos in _configure_twice(driver, listener, '/solo/listener', '/solo/rChat',
                                    'subscription'):
            assert (qos.durability, qos.liveliness_lease_duration.nanoseconds,
                    qos.reliability) == (DurabilityPolicy.TRANSIENT_LOCAL, 4_000_000_000,
                                         ReliabilityPolicy.RELIABLE)
