# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""How a component's lifecycle transitions are named in its log, and refused at shutdown."""

from typing import Any

from rclpy.lifecycle import LifecycleNode

#: What each transition's failure is logged as.
TRANSITION_VERBS = {
    'on_configure': 'configure', 'on_activate': 'activate', 'on_deactivate': 'deactivate',
    'on_cleanup': 'cleanup', 'on_shutdown': 'shutdown', 'on_error': 'error handling'}


def refuse_transitions_after_shutdown(node: LifecycleNode) -> None:
    """
    Answer a transition requested once SIGINT or SIGTERM shut the context down: refused.

    rclpy would start it: rcl moves the state machine (to activating, say),
    fails to publish the transition event on the shut down context, and
    rclpy logs 'Unable to start transition' with the node left in the
    intermediate state. A request taken from DDS after the signal (the
    executor's threads still run) met this in one shutdown in five.
    """
    # rclpy keeps the service (7.1 and 9.1); without it, nothing to guard
    service = getattr(node, '_service_change_state', None)
    if service is None:
        return
    change_state = service.callback

    def answer(request: Any, response: Any) -> Any:
        if not node.context.ok():
            response.success = False
            return response
        return change_state(request, response)

    service.callback = answer
