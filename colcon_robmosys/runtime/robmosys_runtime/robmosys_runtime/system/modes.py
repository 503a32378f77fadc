# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""
A system's modes at run time: the mode it is in, and the switch to another.

``bringup.json`` holds each mode whole (colcon_robmosys.mapping.modes): the
instances active in it, in activation order, and the value every parameter that
some mode sets holds in it. The system comes up in its mode (the others'
instances configured and left inactive, the mode's values set before anything
is activated); a switch then deactivates what the new mode leaves out, those
that come last first, sets the values that change, all of one node's in one
call of its ``set_parameters`` service, and activates what the new mode adds,
in the model's order. The first step that fails ends the switch: the instance
is named, and the system stays where the steps before left it, which
:meth:`Modes.line` tells. A switch asked for during another is refused.
"""

from __future__ import annotations

import threading
import time
from typing import Any, Callable, Dict, List, Optional, Tuple

from lifecycle_msgs.msg import Transition
from rcl_interfaces.srv import SetParameters
from rclpy.node import Node
from rclpy.parameter import Parameter
from robmosys_runtime.system.activation import SystemActivation
from robmosys_runtime.system.lifecycle_calls import Failed, Stopped
from robmosys_runtime.system.switching import SwitchCalls

#: the model's type of a parameter -> rclpy's, for the values a switch sets
_TYPES = {'bool': Parameter.Type.BOOL, 'int': Parameter.Type.INTEGER,
          'double': Parameter.Type.DOUBLE, 'string': Parameter.Type.STRING,
          'bool[]': Parameter.Type.BOOL_ARRAY, 'int[]': Parameter.Type.INTEGER_ARRAY,
          'double[]': Parameter.Type.DOUBLE_ARRAY, 'string[]': Parameter.Type.STRING_ARRAY,
          'byte[]': Parameter.Type.BYTE_ARRAY}


def parameter_message(name: str, value: Any, type_name: Optional[str]) -> Any:
    """Return an rcl_interfaces/Parameter of a value of bringup.json, typed as declared."""
    kind = _TYPES.get(type_name or '')
    if kind is None:
        kind = Parameter.Type.from_parameter_value(value)
    if kind is Parameter.Type.DOUBLE:
        value = float(value)
    elif kind is Parameter.Type.DOUBLE_ARRAY:
        value = [float(v) for v in value]
    elif kind is Parameter.Type.BYTE_ARRAY:
        value = [bytes([v]) if isinstance(v, int) else v for v in value]
    return Parameter(name, kind, value).to_parameter_msg()


class Modes:
    """
    The modes of a system: the one it is in, and the switches between them.

    :param activation: the system's activation, whose lifecycle clients a
        switch uses and whose states it keeps up to date
    :param mode: the mode the system comes up in
    :param report: called with ``(level, text)``
    """

    def __init__(self, node: Node, description: Dict[str, Any], activation: SystemActivation,
                 mode: str, report: Callable[[str, str], None]) -> None:
        self.modes = {m['name']: m for m in description['modes']}
        self._activation = activation
        self._report = report
        instances = description['instances']
        self._types = {i['instance']: {d['name']: d['type'] for d in i.get('declared', ())}
                       for i in instances}
        managed = [i['instance'] for i in instances if i['managed']]
        #: every instance, in activation order (bringup.json's)
        self._order = [i['instance'] for i in instances]
        #: the values each node holds, as far as the manager set them (first the system's)
        self._held = {i['instance']: {p['name']: p['value'] for p in i.get('parameters', ())}
                      for i in instances}
        #: the system's values, those a node is started with
        self._system = {name: dict(values) for name, values in self._held.items()}
        self.mode = mode
        #: the mode a switch under way goes to ('' for none)
        self.switching = ''
        #: why the last switch did not end in its mode ('' when it did)
        self.problem = ''
        self._node = node
        self._fqns = {i['instance']: i['fqn'] for i in instances}
        #: the clients of the switches, made at the first (see switching.py)
        self._calls: Optional[SwitchCalls] = None
        self._lock = threading.Lock()
        activation.held = set(managed) - set(self.modes[mode]['active'])
        activation.configured = self._configured

    def active(self, mode: Optional[str] = None) -> List[str]:
        """Return the instances active in a mode (the current one by default)."""
        return list(self.modes[mode or self.mode]['active'])

    def values(self, mode: Optional[str] = None) -> Dict[str, Dict[str, Any]]:
        """Return instance -> parameter -> value that a mode holds (the current one by default)."""
        return self.modes[mode or self.mode]['values']

    def line(self) -> str:
        """Return the mode the system is in, in one line, for ~/report and /diagnostics."""
        if self.switching:
            return f'mode: {self.mode}, switching to {self.switching}'
        return f'mode: {self.mode}' + (f' (not reached: {self.problem})' if self.problem else '')

    def _configured(self, name: str) -> None:
        """
        Give an instance configured the values of the mode, before it is active.

        At bring-up, and when it was started again (a respawn, ``~/bring_up`` after
        its process ended): it then holds the system's values, which it was started
        with, whatever the manager set before.
        """
        self._held[name] = dict(self._system.get(name, {}))
        changed = {p: v for p, v in self.values().get(name, {}).items()
                   if self._held.get(name, {}).get(p) != v}
        if changed:
            self._set_values(name, changed)

    def switch(self, target: str, *, refuse: str = '') -> Tuple[bool, str]:
        """
        Switch the system to a mode; return whether it got there, and the steps or why not.

        :param refuse: why no switch may start now ('' if one may)
        """
        if target not in self.modes:
            return False, f"no mode '{target}' (modes: {', '.join(self.modes)})"
        if not self._lock.acquire(blocking=False):
            return False, f"refused: the switch to '{self.switching}' is under way"
        try:
            if refuse:
                return False, f'refused: {refuse}'
            origin, self.switching = self.mode, target
            steps: List[str] = []
            try:
                self._steps(target, steps)
            except (Failed, Stopped) as failure:
                self.mode, self.problem = target, str(failure)
                self._report('error', f'mode {target}: the switch from {origin} stopped: '
                             f'{failure}')
                return False, '\n'.join(steps + [f'failed: {failure}'])
            self.mode, self.problem = target, ''
            self._report('info', f'mode {target} (from {origin}): ' + (
                ', '.join(steps) or 'nothing to change'))
            return True, '\n'.join(steps + [f'mode: {target}'])
        finally:
            self.switching = ''
            self._lock.release()

    def _steps(self, target: str, steps: List[str]) -> None:
        """Take the system to a mode, step by step; raise at the first that fails."""
        activation = self._activation
        states = activation.states()
        wanted = self.modes[target]['active']
        order = activation.order()
        # the instances the new mode leaves out: those that come last first
        for name in reversed(order):
            if states.get(name) == 'active' and name not in wanted:
                self._change(name, Transition.TRANSITION_DEACTIVATE, 'inactive')
                activation.held.add(name)
                steps.append(f'deactivate {name}')
        changes = {}
        for name in self._order:
            values = self.modes[target]['values'].get(name, {})
            changed = {p: v for p, v in values.items() if self._held.get(name, {}).get(p) != v}
            if changed:
                changes[name] = changed
        # the nodes' values are independent of each other: every node is asked at once
        answers = self._switch_calls().set_values({name: self._request(name, changed) for
                                                   name, changed in changes.items()},
                                                  max(map(activation.calls.timeout_of,
                                                          changes), default=0.0))
        for name, changed in changes.items():
            self._took(name, changed, answers[name])
            steps.append(f"set {name}: {', '.join(sorted(changed))}")
        # then what it adds, in the model's order (its list is in activation order)
        for name in wanted:
            activation.held.discard(name)
            if activation.states().get(name) != 'active':
                self._change(name, Transition.TRANSITION_ACTIVATE, 'active')
                steps.append(f'activate {name}')
        activation.held = set(activation.held) - set(wanted)

    def _switch_calls(self) -> SwitchCalls:
        """Return the calls of a switch, made at the first."""
        if self._calls is None:
            self._calls = SwitchCalls(self._node, self._fqns)
        return self._calls

    def close(self) -> None:
        """Destroy what the switches made (before the manager's node goes)."""
        if self._calls is not None:
            self._calls.close()

    def _state_of(self, name: str) -> Optional[str]:
        """Return the state an instance tells within a second, None if it does not."""
        try:
            return self._activation.calls.get_state(name, timeout=1.0, failed_too=True)
        except (Failed, Stopped):
            return None

    def _change(self, name: str, transition: int, goal: str) -> None:
        """Take an instance through a transition; a failure names it and marks it failed."""
        try:
            state = self._switch_calls().change(name, transition,
                                                self._activation.calls.timeout_of(name),
                                                lambda: self._state_of(name))
        except Failed as failure:
            self._activation.instance_failed(name, str(failure), report=False)
            raise Failed(f'instance {name} {failure}') from None
        self._activation.set_state(name, state)
        if state != goal:
            raise Failed(f'instance {name} is {state}, not {goal}')

    def _request(self, name: str, values: Dict[str, Any]) -> Any:
        """Return the set_parameters request of values of an instance, typed as declared."""
        return SetParameters.Request(parameters=[
            parameter_message(n, v, self._types.get(name, {}).get(n)) for n, v in values.items()])

    def _set_values(self, name: str, values: Dict[str, Any]) -> None:
        """Set values of one node in one call of its set_parameters; raise if one is refused."""
        calls = self._activation.calls
        wait = calls.timeout_of(name)
        client = calls.client(name, SetParameters, 'set_parameters', wait)
        request = self._request(name, values)
        deadline = time.monotonic() + wait
        attempt = 0.25
        while True:
            # an answer lost while the service's two directions match: asked again
            # (setting the same values twice changes nothing)
            answer = calls.call(client, request, min(attempt, deadline - time.monotonic()))
            if answer is not None or time.monotonic() >= deadline:
                break
            attempt = min(2 * attempt, 2.0)
        self._took(name, values, answer)

    def _took(self, name: str, values: Dict[str, Any], answer: Any) -> None:
        """Keep the values an instance took; raise if it did not answer or refused one."""
        if answer is None:
            wait = self._activation.calls.timeout_of(name)
            raise Failed(f'instance {name} did not answer set_parameters within {wait:g} s')
        refused = [f'{n} = {v!r}: {r.reason}' for (n, v), r in zip(values.items(), answer.results)
                   if not r.successful]
        done = {n: v for (n, v), r in zip(values.items(), answer.results) if r.successful}
        self._held.setdefault(name, {}).update(done)
        if refused:
            raise Failed(f"instance {name} refused {'; '.join(refused)}")
