# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""
The watch of a system on several hosts: each host listens to its own, only a summary travels.

A reader of a topic on the manager's host pulls every sample across the link
from the robot that publishes it, whatever its depth: 2 MB/s of camera
frames become 2 MB/s on Wi-Fi. So the push ports that the watch listens to
for silence are listened to on the host of their publishers: by the manager
for the instances of its own host (those without ``host``), and by each
host's ``bringup --host`` for its own (:class:`HostSummary`), which tells the
manager, every check period, how long ago each of them carried a message
(:class:`Summaries`): a ``diagnostic_msgs/DiagnosticStatus`` of a few hundred
bytes on ``<manager>/hosts``. No message of a modelled topic crosses a link
for the watch. A name that publishers of several hosts share is not listened
to at all (its reader would pull the other hosts' samples).
"""

from __future__ import annotations

import threading
import time
from typing import AbstractSet, Any, Dict, Iterable, Optional, Set, Tuple

from rclpy.node import Node
from rclpy.qos import QoSProfile, ReliabilityPolicy
from robmosys_runtime.sends import Sends
from robmosys_runtime.watch.conformance import Model
from robmosys_runtime.watch.graph import interface

#: matches every publisher, delivers the last message only
_LISTEN = QoSProfile(depth=1, reliability=ReliabilityPolicy.BEST_EFFORT)
#: the summaries of the hosts: the latest of each, every period; a lost one
#: is followed by the next
_SUMMARIES = QoSProfile(depth=16, reliability=ReliabilityPolicy.BEST_EFFORT)
#: periods after which a host's last summary no longer tells of its ports
STALE_PERIODS = 3.0


def watched_names(model: Model) -> Dict[str, Tuple[str, Optional[str]]]:
    """
    Return name -> (type, host that listens) of the push ports watched for silence.

    Those of periodic activities that may not stay quiet. The host that
    listens is the one every publisher of the name runs on ('': the
    manager's host), None where publishers of several hosts share it.
    """
    names: Dict[str, str] = {}
    hosts: Dict[str, Set[str]] = {}
    for instance in model.instances.values():
        for port in instance.get('ports', ()):
            if port.get('period') and not port.get('quiet'):
                names[port['name']] = port['type']
                hosts.setdefault(port['name'], set()).add(instance.get('host') or '')
    return {n: (t, next(iter(hosts[n])) if len(hosts[n]) == 1 else None)
            for n, t in names.items()}


def names_of(watched: Dict[str, Tuple[str, Optional[str]]], host: str) -> Dict[str, str]:
    """Return name -> type of the watched names a host listens to."""
    return {n: t for n, (t, h) in watched.items() if h == host}


def summary_topic(description: Dict[str, Any]) -> str:
    """Return the topic of the hosts' summaries: ``hosts`` of the manager's node."""
    namespace = (description.get('namespace') or '').rstrip('/')
    return f"{namespace}/{description['package']}_bringup/hosts"


def counted_names(model: Model, names: Iterable[str], started: AbstractSet[str]) -> Set[str]:
    """
    Return the names whose every publisher the model has is a generated instance started here.

    Those count their own sends (:mod:`robmosys_runtime.sends`) in the send
    files of the bringup that started them (started: its instances): the
    watch reads the files and needs no copy of their messages. A name that an
    external component publishes too is listened to.
    """
    writers: Dict[str, Set[str]] = {}
    for name, instance in model.instances.items():
        for port in instance.get('ports', ()):
            if port.get('entity') == 'publisher':
                writers.setdefault(port['name'], set()).add(name)
    counting = {n for n in started
                if model.instances.get(n, {}).get('python_class') or
                model.instances.get(n, {}).get('plugin')}
    return {n for n in names if writers.get(n) and writers[n] <= counting}


class Taker:
    """
    Raw subscriptions to watched topics, on a node of their own that no executor spins.

    Each take notes which topics carried a message since the last one (a
    best-effort subscription of depth 1 keeps only the latest, raw). An
    executor would wake up and run Python for every message: 13 % of a CPU
    for 10 topics at 10 Hz (bench_watch.py), where a take per topic and check
    costs next to nothing. The node is made with the first subscription.
    """

    def __init__(self, node: Node, node_name: str) -> None:
        self._parent = node
        self._node_name = node_name
        self.node: Optional[Node] = None
        #: name -> its subscription
        self._taken: Dict[str, Any] = {}
        self.fqn = f"{node.get_namespace().rstrip('/')}/{node_name}"

    def listen(self, names: Dict[str, str]) -> None:
        """Subscribe to names (name -> type) and to no other."""
        for name in [n for n in self._taken if n not in names]:
            assert self.node is not None
            self.node.destroy_subscription(self._taken.pop(name))
        for name, type_name in sorted(names.items()):
            if name in self._taken:
                continue
            try:
                msg_type = interface(type_name)
            except (ImportError, AttributeError, ValueError):
                continue
            self._taken[name] = self._own_node().create_subscription(
                msg_type, name, lambda message: None, _LISTEN, raw=True)

    def _own_node(self) -> Node:
        if self.node is None:
            import rclpy
            # a name of its own: the context's ROS arguments (a __node remapping
            # of the process) are the first node's, not this one's
            self.node = rclpy.create_node(
                self._node_name, namespace=self._parent.get_namespace(),
                context=self._parent.context, start_parameter_services=False,
                enable_rosout=False, use_global_arguments=False)
            self._parent.context.on_shutdown(self.node.destroy_node)
        return self.node

    def take(self, heard: Dict[str, float]) -> None:
        """Note in heard which topics carried a message since the last take."""
        now = time.monotonic()
        for name, subscription in list(self._taken.items()):
            if subscription.handle.take_message(subscription.msg_type, True) is not None:
                heard[name] = now


class Hearing:
    """
    When the watched names of one host last carried a message.

    The names that count their sends (:func:`counted_names`) are read from
    the send files; the others, and a counted one whose publishers keep no
    file (a component built before they did), are listened to by a
    :class:`Taker`.

    :param names: name -> type of the names of this host
    :param sends: the send files of this host's instances, if they keep them
    :param counted: the names whose publishers all count their sends
    """

    def __init__(self, node: Node, names: Dict[str, str], node_name: str,
                 sends: Optional[Sends] = None, counted: AbstractSet[str] = frozenset()) -> None:
        self.names = names
        self._sends = sends
        self._counted = set(counted) if sends is not None else set()
        self.taker = Taker(node, node_name)
        self.taker.listen({n: t for n, t in names.items() if n not in self._counted})

    def take(self, heard: Dict[str, float]) -> None:
        """Note in heard when each name last carried a message, as far as known."""
        if self._counted:
            assert self._sends is not None
            kept = self._sends.latest(self._counted)
            for name, last in kept.items():
                if last is not None and last > heard.get(name, 0.0):
                    heard[name] = last
            self.taker.listen({n: t for n, t in self.names.items() if n not in kept})
        self.taker.take(heard)


class HostSummary:
    """
    A host's part of the watch: its own push ports listened to, a summary sent.

    :param node: the node of the host's ``bringup --host``
    :param names: name -> type of the ports it listens to (:func:`names_of`)
    :param topic: the topic of the summaries (:func:`summary_topic`)
    :param host: the host, as the model names it
    :param sends: the send files of the host's instances, and the names they
        tell (:class:`Hearing`)
    """

    def __init__(self, node: Node, names: Dict[str, str], topic: str, host: str,
                 period: float, sends: Optional[Sends] = None,
                 counted: AbstractSet[str] = frozenset()) -> None:
        from diagnostic_msgs.msg import DiagnosticStatus
        self.host = host
        self.period = period
        self.names = names
        self._hearing = Hearing(node, names, f'{node.get_name()}_watch', sends, counted)
        self._publisher = node.create_publisher(DiagnosticStatus, topic, _SUMMARIES)
        self._started = time.monotonic()
        self.heard: Dict[str, float] = {}

    def send(self) -> None:
        """Take what the watched topics carried, and tell the manager."""
        from diagnostic_msgs.msg import DiagnosticStatus, KeyValue
        self._hearing.take(self.heard)
        now = time.monotonic()
        # how long ago each carried a message ('' never, since the host's watch began)
        values = [KeyValue(key='since', value=f'{now - self._started:.3f}')] + [
            KeyValue(key=name, value=f'{now - self.heard[name]:.3f}' if name in self.heard
                     else '') for name in sorted(self.names)]
        self._publisher.publish(DiagnosticStatus(
            level=DiagnosticStatus.OK, name=f'host {self.host}', hardware_id=self.host,
            message=f'{len(self.names)} watched', values=values))

    def run(self, stopping: threading.Event) -> None:
        """Send a summary every period until stopping is set (a thread's target)."""
        from robmosys_runtime.hosting.output import say
        while not stopping.wait(self.period):
            try:
                self.send()
            except Exception as error:  # noqa: B902 - the host's watch goes on
                say('error', f'the watch of host {self.host} failed: '
                    f'{type(error).__name__}: {error}')


class Summaries:
    """
    The manager's side: when each port of another host last carried a message.

    :param watched: the watched names (:func:`watched_names`)
    :param topic: the topic of the summaries (:func:`summary_topic`)
    :param heard: name -> time.monotonic() it last carried a message, which
        the summaries fill in for the names of other hosts
    """

    def __init__(self, node: Node, watched: Dict[str, Tuple[str, Optional[str]]], topic: str,
                 period: float, heard: Dict[str, float]) -> None:
        from diagnostic_msgs.msg import DiagnosticStatus
        #: name -> the host that listens to it, for the names of other hosts
        self.host_of = {n: h for n, (_, h) in watched.items() if h}
        #: the names no host listens to (publishers on several hosts)
        self.unheard = {n for n, (_, h) in watched.items() if h is None}
        self._period = period
        self._heard = heard
        self._lock = threading.Lock()
        #: host -> time.monotonic() of its last summary
        self._last: Dict[str, float] = {}
        if self.host_of:
            node.create_subscription(DiagnosticStatus, topic, self._on_summary, _SUMMARIES)

    def _on_summary(self, status: Any) -> None:
        now = time.monotonic()
        values = {v.key: v.value for v in status.values}
        with self._lock:
            self._last[status.hardware_id] = now
            for name, ago in values.items():
                if ago and self.host_of.get(name) == status.hardware_id:
                    heard = now - float(ago)
                    if heard > self._heard.get(name, 0.0):
                        self._heard[name] = heard

    def tells(self, name: str) -> bool:
        """Tell whether the silence of a name is known: its host's summary is recent."""
        host = self.host_of.get(name)
        if host is None:
            return name not in self.unheard
        with self._lock:
            last = self._last.get(host)
        return last is not None and time.monotonic() - last <= STALE_PERIODS * self._period
