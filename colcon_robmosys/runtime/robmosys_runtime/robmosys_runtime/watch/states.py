# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""
The lifecycle states of nodes, as each tells them: news without a poll.

Every lifecycle node (rclcpp_lifecycle, rclpy.lifecycle: rcl_lifecycle's
communication interface) publishes each of its transitions on
``<node>/transition_event`` (``lifecycle_msgs/msg/TransitionEvent``).
:class:`LifecycleStates` keeps the last state each node reached, with one
subscription per node: DDS sends a sample only when a transition happens, so
a node that stands still costs nothing. Events are volatile: those of a
transition made before the subscription matched are lost, so a watcher that
must know a state at a given time asks ``get_state`` (see
:mod:`robmosys_runtime.system.drift`); the events tell it when to ask.
"""

from __future__ import annotations

import functools
import threading
from typing import Any, Callable, Dict, List, Mapping, Optional

from rclpy.node import Node
from rclpy.qos import DurabilityPolicy, HistoryPolicy, QoSProfile, ReliabilityPolicy

#: the states a node stays in; the others (configuring, activating...) are on the way
PRIMARY_STATES = frozenset({'unconfigured', 'inactive', 'active', 'finalized'})

#: what rcl_lifecycle publishes its events with (rcl's default publisher options:
#: reliable, volatile, keep last 10), so that every publisher matches
EVENTS_QOS = QoSProfile(history=HistoryPolicy.KEEP_LAST, depth=10,
                        reliability=ReliabilityPolicy.RELIABLE,
                        durability=DurabilityPolicy.VOLATILE)

#: called with (name, state) each time a node reaches a primary state
OnState = Callable[[str, str], None]


class LifecycleStates:
    """
    The last primary state each of some lifecycle nodes reached, from its transition events.

    ``on_state(name, state)`` runs in the executor's thread that spins the node,
    each time a node reaches a primary state (``unconfigured``, ``inactive``,
    ``active``, ``finalized``), whether or not it was in it before: what it
    holds, it holds from every other callback of that executor (give the node
    an executor of its own, or hand the news to a thread). A node's own events
    come in order; nothing is known of a node before its first event.

    One subscription per node: an executor goes over all of them at each of
    its wakes, so a node of their own, with an executor that sleeps until an
    event comes, costs nothing while nothing happens (see
    :meth:`robmosys_runtime.system.drift.Drift.follow`).

    :param node: the node that subscribes (spun by an executor)
    :param nodes: name -> fully qualified node name, of each node to follow
    :param on_state: called at each state reached
    :param callback_group: of the subscriptions (the node's default if None)
    """

    def __init__(self, node: Node, nodes: Mapping[str, str],
                 on_state: Optional[OnState] = None, callback_group: Any = None) -> None:
        from lifecycle_msgs.msg import TransitionEvent
        self._node = node
        self._on_state = on_state
        self._lock = threading.Lock()
        self._states: Dict[str, str] = {}
        self._subscriptions: List[Any] = [
            node.create_subscription(
                TransitionEvent, f"{fqn.rstrip('/')}/transition_event",
                functools.partial(self._event, name), EVENTS_QOS,
                callback_group=callback_group)
            for name, fqn in nodes.items()]

    def state(self, name: str) -> Optional[str]:
        """Return the last primary state a node reached, None if none was told yet."""
        with self._lock:
            return self._states.get(name)

    def states(self) -> Dict[str, str]:
        """Return the last primary state of each node that told one."""
        with self._lock:
            return dict(self._states)

    def forget(self, name: str) -> None:
        """Forget what a node told: its process ended, and a new one tells anew."""
        with self._lock:
            self._states.pop(name, None)

    def close(self) -> None:
        """Destroy the subscriptions (before the node, if it lives on)."""
        for subscription in self._subscriptions:
            self._node.destroy_subscription(subscription)
        self._subscriptions = []

    def _event(self, name: str, event: Any) -> None:
        state = str(event.goal_state.label)
        if state not in PRIMARY_STATES:
            return
        with self._lock:
            self._states[name] = state
        if self._on_state is not None:
            self._on_state(name, state)
