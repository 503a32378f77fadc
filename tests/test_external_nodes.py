# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""Hand-written nodes in a system: external components, on real rclpy.

test_workspace/src/handwritten_nodes is an ordinary ament_python package of two
rclpy nodes nobody generates (a plain talker, a lifecycle listener);
handwritten_system models them as external components and wires them to a
generated relay. The launch files and the system manager start them with their
remappings; the manager brings up the lifecycle one and leaves the plain one be.
A second relay is joined to names outside the model: this test's own node talks
to it there and hears its echo.
"""

from __future__ import annotations

import re
import signal
import sys

import pytest

from colcon_robmosys.devtools.ros_env import background, free_domain_id
from colcon_robmosys.devtools.system import LifecycleDriver, wait_until
from conftest import assert_no_traceback, requires_ros

pytestmark = [pytest.mark.integration, requires_ros]

SYSTEM = 'handwritten_system'


def test_hand_written_nodes_come_up_with_a_generated_one_and_data_flows(test_workspace_built):
    from std_srvs.srv import Trigger
    executable = test_workspace_built.install / SYSTEM / 'lib' / SYSTEM / 'bringup'
    domain_id = free_domain_id()
    with background([sys.executable, str(executable)], env=test_workspace_built.env(domain_id),
                    stop_timeout=30) as bringup, LifecycleDriver(domain_id) as driver:
        # the relays (generated) and the listener (hand-written, lifecycle) are managed;
        # the plain talker is started only
        assert wait_until(lambda: 'bringup: 3 of 3 managed instances active' in
                          bringup.output(), timeout=90), bringup.output()
        # talker --chatter--> relay --heard--> listener, under the nodes' own names
        assert wait_until(lambda: re.search(r'\[listener\]: heard: hello \d+',
                                            bringup.output()) is not None, 30), bringup.output()
        # a node nobody modelled --/outside/words--> echo --/outside/echoes--> it
        from std_msgs.msg import String
        echoes: list[str] = []
        driver.node.create_subscription(String, '/outside/echoes',
                                        lambda msg: echoes.append(msg.data), 10)
        words = driver.node.create_publisher(String, '/outside/words', 10)

        def echoed() -> bool:
            words.publish(String(data='from outside'))
            driver.spin(0.2)
            return 'from outside' in echoes
        assert wait_until(echoed, timeout=30), bringup.output()
        assert wait_until(lambda: '[outside.echo]: relayed: from outside' in bringup.output(),
                          timeout=10), bringup.output()
        assert driver.state('/listener') == 'active'
        report = driver.call(Trigger, f'/{SYSTEM}_bringup/report', Trigger.Request())
        assert report.success, report.message
        assert 'talker: running' in report.message.splitlines(), report.message
        bringup.proc.send_signal(signal.SIGINT)
        assert bringup.proc.wait(timeout=60) == 0, bringup.output()
        output = bringup.output()
    steps = re.findall(r'bringup: (deactivate|cleanup) (\w+)', output)
    # the listener comes after the relay: it goes first; echo with it, in parallel
    assert steps.index(('cleanup', 'listener')) < steps.index(('deactivate', 'relay')), output
    assert sorted(steps) == sorted((step, name) for name in ('listener', 'relay', 'echo')
                                   for step in ('deactivate', 'cleanup')), output
    assert_no_traceback(output)
