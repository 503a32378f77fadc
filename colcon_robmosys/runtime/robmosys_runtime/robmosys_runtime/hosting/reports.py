# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""
What the shared Python process brought up by itself, told to the system manager in one message.

The shared process (``robmosys_runtime.hosting.container --activate``) configures and
activates its managed instances itself. Finding them active with one
``get_state`` each made the manager discover every instance's service in
another process (about 30 DDS endpoints a node: 1500 at 50 instances) before
it could report the system up, and that discovery was what the manager added
to the floor (issue 28). Instead the process tells it, once, on a latched
topic (reliable, transient local: a manager that subscribes later still
gets it): :class:`Reporter` at its end, :class:`Reports` at the manager's.

The topic is ``<namespace>/_<system>_instances/brought_up``, of a hidden node
of the shared process (no parameter services, no rosout: one publisher), with
a ``diagnostic_msgs/DiagnosticStatus``: ``message`` is :data:`STARTING` when
the process has begun (nothing brought up yet), :data:`DONE` once it tried;
``values`` then hold each instance it knows the state of (``key`` the
instance, ``value`` its state: ``active``, or ``unconfigured`` for one it
left to the manager). An instance that failed a transition there is not in
it: the manager asks it (``get_state``), as it asks any instance a process
did not tell it of: an instance of another process or host, or all of them
when no message comes (:data:`GRACE` seconds without one).
"""

from __future__ import annotations

import threading
import time
from typing import Any, Callable, Dict, Iterable, Optional, Set

from diagnostic_msgs.msg import DiagnosticStatus, KeyValue
from rclpy.node import Node
from rclpy.parameter import Parameter
from rclpy.qos import DurabilityPolicy, HistoryPolicy, QoSProfile, ReliabilityPolicy

#: the process has begun, and will tell what it brought up
STARTING = 'starting'
#: the process tried to bring its instances up: the values are their states
DONE = 'brought up'

#: seconds the manager waits for any message of the process before it asks
#: the instances themselves (a process that does not tell: it does not
#: --activate, or was started by an older launch file)
GRACE = 10.0

#: latched: the last message of each process reaches a manager that comes later
QOS = QoSProfile(history=HistoryPolicy.KEEP_LAST, depth=10,
                 reliability=ReliabilityPolicy.RELIABLE,
                 durability=DurabilityPolicy.TRANSIENT_LOCAL)


def reporter_name(package: str) -> str:
    """Return the (hidden) node name of the shared process that reports to the manager."""
    return f'_{package}_instances'


def report_topic(description: Dict[str, Any]) -> str:
    """Return the topic where a system's shared process tells what it brought up."""
    return (f"{description.get('namespace', '')}/{reporter_name(description['package'])}"
            '/brought_up')


class Reporter:
    """
    The shared process's end: tells the manager which instances it brought to which state.

    :meth:`make` creates its node, first in the process (its publisher is
    discovered before the instances' endpoints) and says :data:`STARTING`.
    """

    def __init__(self, description: Dict[str, Any], context: Any = None) -> None:
        self._description = description
        self._context = context
        self._publisher: Any = None
        self.node: Optional[Node] = None

    def make(self) -> Node:
        """Create the node and its publisher; say the process began."""
        namespace = self._description.get('namespace') or None
        self.node = Node(
            reporter_name(self._description['package']), namespace=namespace,
            context=self._context, use_global_arguments=False, enable_rosout=False,
            start_parameter_services=False,
            parameter_overrides=[Parameter('start_type_description_service', value=False)])
        self._publisher = self.node.create_publisher(
            DiagnosticStatus, report_topic(self._description), QOS)
        self._publish(STARTING, {})
        return self.node

    def brought_up(self, states: Dict[str, str]) -> None:
        """Tell the state of each instance (instance -> state) the process knows for sure."""
        self._publish(DONE, states)

    def _publish(self, what: str, states: Dict[str, str]) -> None:
        self._publisher.publish(DiagnosticStatus(
            level=DiagnosticStatus.OK, name=reporter_name(self._description['package']),
            message=what, values=[KeyValue(key=k, value=v) for k, v in sorted(states.items())]))


class Reports:
    """
    The manager's end: the state the shared process told for each of its instances.

    Each told state is taken once, by the first bring-up of its instance
    (:meth:`take`): a later one (the instance was brought down, or its
    process started again) asks the instance itself.

    :param expected: the instances a process is to tell of (those of the
        shared process that brings itself up): only those are waited for
    :param grace: seconds to wait for any message, before asking the instances
    :param patience: seconds to wait for the state of an instance once its
        process said it began (it makes and brings up every node in turn)
    """

    def __init__(self, node: Node, description: Dict[str, Any], expected: Iterable[str],
                 grace: float = GRACE, patience: float = 60.0) -> None:
        self._expected = set(expected)
        self._grace = grace
        self._patience = patience
        self._since = time.monotonic()
        self._states: Dict[str, str] = {}
        self._begun = False
        self._done = False
        self._taken: Set[str] = set()
        self._changed = threading.Condition()
        self.subscription = node.create_subscription(
            DiagnosticStatus, report_topic(description), self._heard, QOS) \
            if self._expected else None

    def told(self, states: Dict[str, str]) -> None:
        """
        Take the states the processes told otherwise (``bringup`` reads them from pipes).

        The C++ container tells only so: its instances are expected once told.
        """
        with self._changed:
            self._expected.update(states)
            self._begun = self._done = True
            self._states.update(states)
            self._changed.notify_all()

    def _heard(self, message: DiagnosticStatus) -> None:
        with self._changed:
            self._begun = True
            if message.message == DONE:
                self._done = True
                self._states.update((v.key, v.value) for v in message.values)
            self._changed.notify_all()

    def take(self, name: str, stopped: Callable[[], bool]) -> Optional[str]:
        """
        Return the state told of an instance at its first bring-up; None where none is.

        Waits while its process may still tell it; returns None at once for
        an instance no process is to tell of, or brought up before, or left
        out of what its process told, and when ``stopped()`` (the bring-up
        ends).
        """
        with self._changed:
            first = name not in self._taken
            self._taken.add(name)
            if not first or name not in self._expected:
                return None
            while name not in self._states:
                waited = time.monotonic() - self._since
                # told of the others only: it failed a transition there
                if self._done or stopped() or \
                        waited > (self._patience if self._begun else self._grace):
                    return None
                self._changed.wait(0.25)
            return self._states[name]
