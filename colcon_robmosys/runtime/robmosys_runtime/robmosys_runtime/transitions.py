# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""How a component's lifecycle transitions are named in its log, and guarded at its end."""

import threading
import time
from typing import Any, Iterable, List
from weakref import WeakKeyDictionary

from rclpy.lifecycle import LifecycleNode
from rclpy.node import Node

#: What each transition's failure is logged as.
TRANSITION_VERBS = {
    'on_configure': 'configure', 'on_activate': 'activate', 'on_deactivate': 'deactivate',
    'on_cleanup': 'cleanup', 'on_shutdown': 'shutdown', 'on_error': 'error handling'}

#: seconds the end of a process waits for a transition under way to finish
TRANSITION_GRACE = 3.0


class TransitionGuard:
    """
    The transitions a node is asked for, one at a time; none once its process ends.

    rclpy starts a requested transition whatever the state of its context:
    rcl moves the state machine (to activating, say), fails to publish the
    transition event once the context is shut down, and rclpy logs 'Unable
    to start transition' or 'Failed to complete transition', with the node
    left in the intermediate state. A SIGINT that came while a transition ran
    (one Ctrl-C in five under load, issue 28) or a request taken from DDS
    after it met this. The process's end closes the guard (:meth:`close`),
    refusing the others, and waits for the transition under way (:meth:`settle`).
    """

    def __init__(self) -> None:
        """Make a guard, open."""
        self._lock = threading.Lock()
        self._closed = False

    def answer(self, node: Node, change_state: Any, request: Any, response: Any) -> Any:
        """Answer a request of the node's change_state service: refused once closed."""
        if not self._closed:  # refused at once, while a transition under way ends
            with self._lock:
                if not self._closed and node.context.ok():
                    return change_state(request, response)
        response.success = False
        return response

    def close(self) -> None:
        """Refuse every request from now on."""
        self._closed = True

    def settle(self, timeout: float) -> bool:
        """Return once no request is answered; False if one still is after timeout."""
        if not self._lock.acquire(timeout=max(timeout, 0.0)):
            return False
        self._lock.release()
        return True


_GUARDS: 'WeakKeyDictionary[Node, TransitionGuard]' = WeakKeyDictionary()


def guard_transitions(node: LifecycleNode) -> None:
    """Answer the node's transition requests through a :class:`TransitionGuard`."""
    # rclpy keeps the service (7.1 and 9.1); without it, nothing to guard
    service = getattr(node, '_service_change_state', None)
    if service is None:
        return
    change_state = service.callback
    guard = _GUARDS[node] = TransitionGuard()
    service.callback = lambda request, response: guard.answer(
        node, change_state, request, response)


def close_transitions(nodes: Iterable[Node], timeout: float = TRANSITION_GRACE) -> List[Node]:
    """
    Close the guard of each node (:func:`guard_transitions`), within timeout in all.

    Return the nodes whose transition under way had not finished by then.
    """
    deadline = time.monotonic() + timeout
    guarded = [(node, _GUARDS[node]) for node in nodes if node in _GUARDS]
    for _, guard in guarded:
        guard.close()
    return [node for node, guard in guarded if not guard.settle(deadline - time.monotonic())]
