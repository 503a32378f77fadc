# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""The test driver's lifecycle calls, against a real ROS 2 service in another process."""

import sys

import pytest

from colcon_robmosys.devtools import ros_env
from colcon_robmosys.devtools.system import LifecycleDriver, wait_until
from conftest import requires_ros

pytestmark = [pytest.mark.integration, requires_ros]

# A node that serves /late/change_state and /late/get_state as a lifecycle node
# whose first answer comes after the driver stopped waiting for it: the first
# configure takes 7 s; get_state answers meanwhile (another callback group);
# a second configure waits for the first, and then fails, being asked of
# 'inactive'. It is how a request delivered late, not lost, looks to the driver.
_LATE_SERVER = """
import threading
import time

import rclpy
from rclpy.callback_groups import MutuallyExclusiveCallbackGroup
from rclpy.executors import MultiThreadedExecutor
from lifecycle_msgs.msg import State
from lifecycle_msgs.srv import ChangeState, GetState

rclpy.init()
node = rclpy.create_node('late')
lock = threading.Lock()
state = ['unconfigured']
asked = []


def change(request, response):
    asked.append(request.transition.id)
    with lock:
        if len(asked) == 1:
            time.sleep(7.0)
        response.success = state[0] == 'unconfigured'
        state[0] = 'inactive'
        print('answered', response.success, flush=True)
    return response


def get(request, response):
    response.current_state = State(label=state[0])
    return response


node.create_service(ChangeState, '/late/change_state', change,
                    callback_group=MutuallyExclusiveCallbackGroup())
node.create_service(GetState, '/late/get_state', get,
                    callback_group=MutuallyExclusiveCallbackGroup())
print('ready', flush=True)
executor = MultiThreadedExecutor(num_threads=3)
executor.add_node(node)
try:
    executor.spin()
except KeyboardInterrupt:
    node.destroy_node()
    rclpy.try_shutdown()
"""


def test_a_transition_asked_again_while_the_first_came_late_is_done(domain_id):
    env = ros_env.loopback_env(domain_id)
    with ros_env.background([sys.executable, '-c', _LATE_SERVER], env=env) as server, \
            LifecycleDriver(domain_id) as driver:
        assert wait_until(lambda: 'ready' in server.output(), 30), server.output()
        # the second request fails, but the node is where the transition leads
        assert driver.transition('/late', 'configure', timeout=30)
        assert wait_until(lambda: server.output().count('answered') == 2, 10), \
            server.output()
        assert 'answered True' in server.output()
        assert 'answered False' in server.output()
        assert driver.state('/late') == 'inactive'
