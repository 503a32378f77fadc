# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""
The manager of a system with modes: it comes up in one and switches on request.

``~/set_mode/<mode>`` (std_srvs/Trigger, one service per mode of the model)
switches the system (:class:`~robmosys_runtime.system.modes.Modes`); the
answer lists the steps, or why the switch was refused or where it stopped.
``~/report`` and ``/diagnostics`` name the mode.

One Trigger service per mode, not one service with the mode's name in its
request: no type in the ROS 2 wheels carries a name in and a reason out
(std_srvs has none with a string; reusing one of another meaning, such as
diagnostic_msgs/AddDiagnostics' ``load_namespace``, would read wrong), and a
type of robmosys_runtime's own would make it an interface package, generated
for every language before any system builds. The mode in the service's name
is what ``ros2 service call`` needs (``ros2 service call
/<system>_bringup/set_mode/cruising std_srvs/srv/Trigger``), ``ros2 service
list`` shows the modes, and a mode the model lacks has no service to call.
"""

from __future__ import annotations

import argparse
from types import SimpleNamespace
from typing import Any, Dict, Tuple

from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus, KeyValue
from rclpy.callback_groups import ReentrantCallbackGroup
from rclpy.node import Node
from robmosys_runtime.hosting.output import guarded, say
from robmosys_runtime.system.manager import Manager
from robmosys_runtime.system.modes import Modes
from robmosys_runtime.watch.watcher import Watch
from std_srvs.srv import Trigger


class ModedManager(Manager):
    """
    The manager of a system with modes (``bringup.json`` holds them).

    :param args: bringup's options; ``args.mode`` is the mode to come up in
    """

    def __init__(self, node: Node, description: Dict[str, Any], params_file: str,
                 args: argparse.Namespace, *rest: Any, **kwargs: Any) -> None:
        # the services and the timer of Manager start before this is made: until it is,
        # they answer as for a system without modes (see _made)
        self._made = False
        super().__init__(node, description, params_file, args, *rest, **kwargs)
        self.modes = Modes(node, description, self.activation,
                           args.mode or description['initial_mode'], say)
        # reentrant: a switch asked for during another is answered (refused) at once
        group = ReentrantCallbackGroup()
        for name in self.modes.modes:
            node.create_service(Trigger, f'~/set_mode/{name}', guarded(
                f'set_mode/{name}', lambda request, response, name=name:
                    self._set_mode(name, response)), callback_group=group)
        self._made = True

    def steady(self) -> bool:
        """Tell whether the states of the instances are the system's: not while switching."""
        return super().steady() and not (self._made and self.modes.switching)

    def _set_mode(self, name: str, response: Any) -> Any:
        refuse = ''
        if self.activation.running():
            refuse = 'the system is being brought up'
        elif not self.up:
            refuse = 'the system is brought down (~/bring_up first)'
        watch = self.watch
        if watch is not None and not refuse and not self.modes.switching and \
                name in self.modes.modes:
            # the values it sets are the new mode's from the first (and if it stops
            # halfway, the system is still meant to be in it)
            watch.expect(name, set(self.managed) - set(self.modes.active(name)),
                         self.modes.values(name), self.modes.modes[name].get('location', ''))
        response.success, response.message = self.modes.switch(name, refuse=refuse)
        if watch is not None:
            self._expect(watch)
        return response

    def _bring_up(self, request: Any, response: Any) -> Any:
        """
        Bring the system up in its mode; after a switch that stopped, finish that switch.

        The instances come up as the mode has them; then the steps of the switch
        that did not happen (values not set, instances not activated) are made,
        and ``~/report`` no longer says the mode was not reached.
        """
        response = super()._bring_up(request, response)
        if self._made and response.success and self.modes.problem:
            done, steps = self.modes.switch(self.modes.mode)
            response.success = done
            response.message += f'\nmode {self.modes.mode}: ' + ', '.join(steps.splitlines())
        return response

    def page_hooks(self) -> Dict[str, Any]:
        """Return what the page (system/page.py's serve_page) shows of the modes, and asks."""
        def switch(arguments: Dict[str, Any]) -> Tuple[bool, str]:
            answer = self._set_mode(str(arguments.get('mode', '')),
                                    SimpleNamespace(success=False, message=''))
            return bool(answer.success), str(answer.message)
        return {'extra': {'mode': switch}, 'mode': lambda: self.modes.mode,
                'modes': lambda: list(self.modes.modes)}

    def _expect(self, watch: Watch) -> None:
        """Have the watch compare with the mode the system is in (or switches to)."""
        mode = self.modes.modes[self.modes.mode]
        watch.expect(mode['name'], set(self.managed) - set(mode['active']), mode['values'],
                     mode.get('location', ''))

    def state_report(self) -> str:
        """Return the mode, then one line per instance."""
        if not self._made:
            return super().state_report()
        return f'{self.modes.line()}\n{super().state_report()}'

    def _report(self, request: Any, response: Any) -> Any:
        response = super()._report(request, response)
        if not self._made:
            response.success = False
            return response
        response.success = response.success and not self.modes.problem and \
            not self.modes.switching
        return response

    def publish_diagnostics(self) -> None:
        """Publish the state of every instance on /diagnostics, and the mode first."""
        if not self._made:
            return
        publisher = self._diagnostics
        self._diagnostics = _First(self._mode_status(), publisher)
        try:
            super().publish_diagnostics()
        finally:
            self._diagnostics = publisher

    def _mode_status(self) -> DiagnosticStatus:
        modes = self.modes
        level = DiagnosticStatus.ERROR if modes.problem else \
            DiagnosticStatus.WARN if modes.switching else DiagnosticStatus.OK
        return DiagnosticStatus(
            level=level, name=f"{self.description['package']}: mode",
            message=modes.line(), hardware_id=self.node.get_fully_qualified_name(),
            values=[KeyValue(key='mode', value=modes.mode),
                    KeyValue(key='switching', value=modes.switching),
                    KeyValue(key='active', value=', '.join(modes.active()))])


class _First:
    """A publisher of diagnostics that puts one status first in every array it publishes."""

    def __init__(self, status: DiagnosticStatus, publisher: Any) -> None:
        self._status = status
        self._publisher = publisher

    def publish(self, array: DiagnosticArray) -> None:
        array.status.insert(0, self._status)
        self._publisher.publish(array)
