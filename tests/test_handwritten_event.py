# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""A hand-written rclpy node serves an event port to a generated component, on real ROS 2.

test_workspace's hand_level_sensor is an ordinary ament_cmake package (rclpy): its node
serves the event port eLevel with robmosys_runtime's EventServer. The generated
level_watcher requires that port; it activates the event continuously and once.
"""

from __future__ import annotations

import contextlib
import re

import pytest

from colcon_robmosys.devtools.ros_env import background
from colcon_robmosys.devtools.system import LifecycleDriver, wait_until
from conftest import assert_no_traceback, requires_ros

pytestmark = [pytest.mark.integration, requires_ros]

THRESHOLD = 15  # level_watcher's default


def test_events_of_a_hand_written_server_reach_a_generated_component(
        test_workspace_built, domain_id):
    install = test_workspace_built.install
    env = test_workspace_built.env(domain_id)
    sensor_cmd = [str(install / 'hand_level_sensor' / 'lib' / 'hand_level_sensor' /
                      'hand_level_sensor')]
    watcher_cmd = [str(install / 'level_watcher' / 'lib' / 'level_watcher' / 'LevelWatcher'),
                   '--ros-args', '-r', '__node:=watcher']
    with contextlib.ExitStack() as stack:
        sensor = stack.enter_context(background(sensor_cmd, env=env))
        watcher = stack.enter_context(background(watcher_cmd, env=env))
        driver = stack.enter_context(LifecycleDriver(domain_id))
        assert driver.state('/watcher') == 'unconfigured', watcher.output()
        assert driver.transition('/watcher', 'configure'), watcher.output()
        assert driver.transition('/watcher', 'activate'), watcher.output()

        def levels() -> list[int]:
            return [int(n) for n in re.findall(r'event: level (\d+)', watcher.output())]
        assert wait_until(lambda: len(levels()) >= 6, 30), watcher.output() + sensor.output()
        # only the levels the activation's threshold lets through
        assert set(levels()) >= {15, 16, 17, 18, 19}
        assert all(level >= THRESHOLD for level in levels())
        # the single activation ended with its first event
        assert wait_until(lambda: 'single activation: 1 event(s), ended: True'
                          in watcher.output(), 20), watcher.output()
        # the server saw the activations: each level at or above 15 went to two
        # of them (continuous and single) or one, never to the threshold 100
        notified = re.findall(r'level (\d+) notified to (\d+)', sensor.output())
        assert notified and all(int(level) >= THRESHOLD for level, _ in notified)
        assert 'never activation: 0 event(s), ended: False' in watcher.output()
        assert driver.transition('/watcher', 'deactivate'), watcher.output()
        for process in (sensor, watcher):
            assert_no_traceback(process.output())
