# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""``bringup --check`` asks an instance its state again when an answer is lost."""

import time
from types import SimpleNamespace

from lifecycle_msgs.srv import GetState
import rclpy
from rclpy.callback_groups import ReentrantCallbackGroup
from rclpy.task import Future
from robmosys_runtime.watch import check


def test_an_instance_whose_first_answer_is_lost_is_asked_again(spinning):
    # rmw_fastrtps drops an answer to a client whose reader of answers the server has
    # not matched yet; through a discovery server a new participant's endpoints reach
    # the other hosts a while after it sees theirs: the first answer never comes
    server = spinning.add(rclpy.create_node('lossy', context=spinning.context))
    asked = []
    never = Future()

    async def get_state(request, response):
        asked.append(time.monotonic())
        if len(asked) == 1:
            await never
        response.current_state.label = 'active'
        return response

    server.create_service(GetState, '/lossy/get_state', get_state,
                          callback_group=ReentrantCallbackGroup())
    checker = spinning.add(rclpy.create_node('checker', context=spinning.context))
    model = SimpleNamespace(instances={
        'lossy': {'managed': True, 'fqn': '/lossy'},
        'absent': {'managed': True, 'fqn': '/absent'},
        'external': {'managed': False, 'fqn': '/external'}})
    try:
        start = time.monotonic()
        states = check._states(checker, model, {'/lossy', '/external'}, timeout=8.0)
    finally:
        never.cancel()
    assert states == {'lossy': 'active', 'absent': 'absent', 'external': 'running'}
    assert len(asked) == 2
    # asked again after 2 s, not at the end of the timeout
    assert asked[1] - start < 5.0
