# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""
The conformance watch: the system manager holds the running system to its model.

Every check period, :class:`Watch` reads the ROS graph once for the names of
the model (each end's node, type and QoS), keeps the parameter values
``/parameter_events`` tells, notes when the push ports of periodic activities
last carried a message (from the send times the instances keep, or a raw
subscription each: no message is deserialized),
and compares (:func:`robmosys_runtime.watch.conformance.compare`). Each difference
is reported once when it appears and once when it clears, at the model's
line. :mod:`robmosys_runtime.watch.check` does the same once, for ``bringup --check``.
"""

from __future__ import annotations

import threading
import time
from typing import AbstractSet, Any, Callable, Dict, Iterable, List, Optional

from rclpy.node import Node
from rclpy.qos import qos_profile_parameter_events
from robmosys_runtime.sends import Sends
from robmosys_runtime.watch.conformance import compare, Difference, Model, State
from robmosys_runtime.watch.graph import GraphReader
from robmosys_runtime.watch.hosts import (
    counted_names, Hearing, names_of, Summaries, summary_topic, watched_names)


class Listener:
    """
    When each watched name last carried a message, and the parameters nodes tell.

    The manager reads when the instances of its own host last sent on the
    watched push ports, or listens to them (:class:`~robmosys_runtime.watch.hosts.Hearing`,
    each check); each
    other host's ``bringup --host`` to its own, and tells how long ago each
    carried a message (:class:`~robmosys_runtime.watch.hosts.Summaries`).
    """

    def __init__(self, node: Node, model: Model, description: Dict[str, Any],
                 period: float, sends: Optional[Sends] = None,
                 started: AbstractSet[str] = frozenset()) -> None:
        self.heard: Dict[str, float] = {}
        self.parameters: Dict[str, Dict[str, Any]] = {}
        self._lock = threading.Lock()
        watched = watched_names(model)
        self.names = {n: t for n, (t, _) in watched.items()}
        local = names_of(watched, '')
        self._hearing = Hearing(node, local, f'{node.get_name()}_watch', sends,
                                counted_names(model, local, started)) if local else None
        #: the node of the watched topics, if any ('' otherwise)
        self.node_name = self._hearing.taker.fqn if self._hearing else ''
        self._summaries = Summaries(node, watched, summary_topic(description), period,
                                    self.heard)
        from rcl_interfaces.msg import ParameterEvent
        self._watched = {i['fqn'] for i in model.instances.values() if i.get('parameters')}
        node.create_subscription(ParameterEvent, '/parameter_events', self._on_parameters,
                                 qos_profile_parameter_events)

    def take(self) -> None:
        """Note which watched topics of this host carried a message since the last take."""
        if self._hearing is not None:
            self._hearing.take(self.heard)

    def tells(self, name: str) -> bool:
        """Tell whether the silence of a watched name is known here and now."""
        return self._summaries.tells(name)

    def _on_parameters(self, event: Any) -> None:
        if event.node not in self._watched:
            return
        from rclpy.parameter import parameter_value_to_python
        with self._lock:
            values = self.parameters.setdefault(event.node, {})
            for parameter in list(event.new_parameters) + list(event.changed_parameters):
                values[parameter.name] = parameter_value_to_python(parameter.value)

    def keep(self, node: str, values: Dict[str, Any]) -> None:
        """Keep values read from a node, unless an event told newer ones meanwhile."""
        with self._lock:
            known = self.parameters.setdefault(node, {})
            for name, value in values.items():
                known.setdefault(name, value)

    def values(self) -> Dict[str, Dict[str, Any]]:
        """Return a copy of the parameter values seen, by node."""
        with self._lock:
            return {n: dict(v) for n, v in self.parameters.items()}


class Watch:
    """
    The system manager's conformance watch.

    The graph tells of a new endpoint a moment after it is made (discovery),
    so the ports of an instance are checked from ``grace`` seconds after it
    became active, and a difference is reported once two checks in a row
    found it: a false alarm costs more than one check period of delay.

    :param report: called with each difference that appears (True) or clears (False)
    :param sends: the send files of the instances this process started (started)
    """

    def __init__(self, node: Node, description: Dict[str, Any], *, period: float,
                 silence: float,
                 report: Optional[Callable[[Difference, bool], None]] = None,
                 grace: Optional[float] = None, confirm: int = 2,
                 sends: Optional[Sends] = None, started: AbstractSet[str] = frozenset()) -> None:
        self.period = period
        self.silence = silence
        self.grace = max(2 * period, 3.0) if grace is None else grace
        self.confirm = confirm
        self._seen: Dict[str, int] = {}
        self._settled_since: Optional[float] = None
        #: checks in a row that saw the whole system up for longer than the grace
        self._whole_checks = 0
        self.model = Model(description, own_nodes=[node.get_fully_qualified_name()])
        self._node = node
        self._reader = GraphReader(node, self.model)
        #: instances whose parameters were read since they came up
        self._read: set = set()
        self._listener = Listener(node, self.model, description, period, sends, started)
        if self._listener.node_name:
            self.model.nodes.add(self._listener.node_name)
        self._report = report or _say
        self._up_since: Dict[str, float] = {}
        #: the differences of the last check, by key
        self.differences: Dict[str, Difference] = {}
        #: whether the last check compared (the graph named every end)
        self.compared = False
        #: the mode compared with ('' for a system without modes), and the state each
        #: managed instance is to be in where it is not active (see expect)
        self.mode = ''
        self.expected: Dict[str, str] = {}

    def expect(self, mode: str, inactive: Iterable[str], values: Dict[str, Dict[str, Any]],
               location: str) -> None:
        """
        Compare with a mode of the system from now on.

        :param inactive: the managed instances the mode leaves inactive
        :param values: instance -> parameter -> the value it holds in the mode
        :param location: where the model writes the mode: its values' location
        """
        self.mode = self.model.mode = mode
        self.expected = dict.fromkeys(inactive, 'inactive')
        for name, given in values.items():
            instance = self.model.instances.get(name)
            if instance is not None:
                self.model.instances[name] = dict(instance, parameters=[
                    dict(p, value=given[p['name']], location=location)
                    if p['name'] in given else p for p in instance.get('parameters', ())])

    def check(self, states: Dict[str, str], settled: bool) -> Dict[str, Difference]:
        """Compare the system with its model once; report what appeared and cleared."""
        self._listener.take()
        graph = self._reader.read()
        self.compared = graph.complete
        if not graph.complete:
            # the graph does not name every end yet (a node just made, or the
            # names lost with a lease): what it leaves out is no ground for a
            # difference, and what the last checks found stands
            return self.differences
        now = time.monotonic()
        state = State(parameters=self._listener.values())
        if not settled:
            self._settled_since = None
        elif self._settled_since is None:
            self._settled_since = now
        steady = self._settled_since is not None and now - self._settled_since >= self.grace
        for name, instance in self.model.instances.items():
            current = states.get(name, 'starting')
            goal = self.expected.get(name, 'active')
            # every instance the model starts runs, once the system is up
            state.present[name] = steady and (current == goal or not instance['managed'])
            if instance['managed']:
                up = settled and current == 'active'
                if settled and current not in (goal, 'starting'):
                    state.wrong_state[name] = f'is {current}, not {goal}' + (
                        f' (mode {self.mode})' if self.mode else '')
            else:
                # a plain node shows its ports as soon as it runs; a lifecycle node
                # that the system leaves unconfigured has none to show
                up = not instance.get('lifecycle', True) and instance['fqn'] in graph.nodes
            if not up:
                self._up_since.pop(name, None)
                self._read.discard(name)
            else:
                self._up_since.setdefault(name, now)
            state.up[name] = up and now - self._up_since[name] >= self.grace
        # values set before the manager listened: asked once of each instance that came up
        newly = [n for n, up in state.up.items() if up and n not in self._read]
        if newly:
            self._read.update(newly)
            read_parameters(self._node, [self.model.instances[n] for n in newly],
                            self._listener, timeout=max(self.period, 1.0))
            state.parameters = self._listener.values()
        state.silent = self.silent(state.up, now)
        whole = steady and all(state.up[n] for n, i in self.model.instances.items()
                               if i['managed'] and states.get(n) == 'active')
        self._whole_checks = self._whole_checks + 1 if whole else 0
        found = compare(self.model, graph, state)
        self._seen = {key: self._seen.get(key, 0) + 1 for key in found}
        confirmed = {key: d for key, d in found.items()
                     if self._seen[key] >= self.confirm or key in self.differences}
        for key, difference in confirmed.items():
            if key not in self.differences:
                self._report(difference, True)
        for key, difference in self.differences.items():
            if key not in found:
                self._report(difference, False)
        self.differences = confirmed
        return confirmed

    @property
    def ready(self) -> bool:
        """Tell whether the last checks compared the whole system, as long as a report takes."""
        return self._whole_checks >= self.confirm

    def silent(self, up: Dict[str, bool], now: float) -> Dict[str, float]:
        """Return instance.port -> seconds of silence, of the watched ports silent too long."""
        silent = {}
        for name, instance in self.model.instances.items():
            if not up.get(name):
                continue
            for port in instance.get('ports', ()):
                if not port.get('period') or port.get('quiet') or \
                        port['name'] not in self._listener.names or \
                        not self._listener.tells(port['name']):
                    continue
                threshold = max(self.silence * port['period'], 2 * self.period)
                since = max(self._up_since[name], self._listener.heard.get(port['name'], 0.0))
                if now - since > threshold:
                    silent[f"{name}.{port['port']}"] = now - since
        return silent

    def run(self, stopping: threading.Event, states: Callable[[], Dict[str, str]],
            settled: Callable[[], bool]) -> None:
        """Check every period until stopping is set (a thread's target)."""
        from robmosys_runtime.hosting.output import say
        while not stopping.wait(self.period):
            try:
                self.check(states(), settled())
            except Exception as error:  # noqa: B902 - the watch goes on
                say('error', f'the conformance watch failed: {type(error).__name__}: {error}')

    def parameter_values(self) -> Dict[str, Dict[str, Any]]:
        """Return the parameter values seen at run time, by node (the manager's page)."""
        return self._listener.values()

    def by_subject(self) -> Dict[str, List[Difference]]:
        """Return the current differences by status (``instance <n>``, ``connection <i>``)."""
        subjects: Dict[str, List[Difference]] = {}
        for difference in sorted(self.differences.values(), key=lambda d: d.key):
            subjects.setdefault(difference.subject, []).append(difference)
        return subjects


def _say(difference: Difference, appeared: bool) -> None:
    from robmosys_runtime.hosting.output import say
    if appeared:
        say('info', f'{difference.location}: difference: {difference.message}')
    else:
        say('info', f'{difference.location}: cleared: {difference.message}')


def read_parameters(node: Node, instances: List[Dict[str, Any]], listener: Listener,
                    timeout: float) -> None:
    """Ask instances the values of the parameters the model sets; keep them in listener."""
    from rcl_interfaces.srv import GetParameters
    from rclpy.parameter import parameter_value_to_python
    pending = []
    for instance in instances:
        names = [p['name'] for p in instance.get('parameters', ())]
        if not names:
            continue
        client: Any = node.create_client(GetParameters, f"{instance['fqn']}/get_parameters")
        if not client.wait_for_service(timeout_sec=timeout):
            node.destroy_client(client)
            continue
        pending.append((instance['fqn'], names, client,
                        client.call_async(GetParameters.Request(names=names))))
    deadline = time.monotonic() + timeout
    for fqn, names, client, future in pending:
        while not future.done() and time.monotonic() < deadline:
            time.sleep(0.02)
        answer = future.result() if future.done() else None
        if answer is not None:
            listener.keep(fqn, {name: parameter_value_to_python(value)
                                for name, value in zip(names, answer.values)
                                if value.type})  # 0: not set
        node.destroy_client(client)


def watch_diagnostics(watch: Watch, array: Any) -> None:
    """
    Add the differences to the statuses of /diagnostics.

    An instance's status takes those about it (ERROR, each in a value
    ``difference``, with ``location``); each connection has a status of its
    own, named ``<system>: <from> -> <to>``, its ROS name the hardware id.
    """
    from diagnostic_msgs.msg import DiagnosticStatus, KeyValue
    model = watch.model
    subjects = watch.by_subject()
    by_name = {s.name: s for s in array.status}
    for name, instance in model.instances.items():
        status = by_name.get(f'{model.package}: {name}')
        differences = subjects.get(f'instance {name}', [])
        if status is None:
            continue
        status.values.append(KeyValue(key='location', value=instance.get('location', '')))
        if differences:
            status.level = DiagnosticStatus.ERROR
            status.message = f'{status.message}; {differences[0].message}'
            status.values += [KeyValue(key='difference', value=d.line()) for d in differences]
    for index, connection in enumerate(model.connections):
        differences = subjects.get(f'connection {index}', [])
        array.status.append(DiagnosticStatus(
            level=DiagnosticStatus.ERROR if differences else DiagnosticStatus.OK,
            name=f'{model.package}: {model.connection_label(index)}',
            message=differences[0].message if differences else 'as the model says',
            hardware_id=connection['name'],
            values=[KeyValue(key='location', value=connection.get('location', '')),
                    KeyValue(key='type', value=connection['type'])] +
            [KeyValue(key='difference', value=d.line()) for d in differences]))
