# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""
The system manager: the processes of a system, their bring-up, what operators see.

:class:`Manager` starts the instances a system package describes (``bringup.json``),
brings the managed ones up with :class:`~robmosys_runtime.system.activation.SystemActivation`,
and offers operators services and ``/diagnostics``; ``ros2 run <system> bringup``
(:mod:`robmosys_runtime.system.bringup`) runs it in the foreground.
"""

from __future__ import annotations

import argparse
import threading
from typing import Any, Dict, Optional

from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus, KeyValue
from rclpy.callback_groups import MutuallyExclusiveCallbackGroup
from rclpy.executors import Executor
from rclpy.node import Node
from robmosys_runtime.hosting.output import failure_text, guarded, say
from robmosys_runtime.hosting.processes import Groups, plan_processes, shared_python
from robmosys_runtime.hosting.reports import GRACE, Reports
from robmosys_runtime.hosting.supervision import Processes
from robmosys_runtime.sends import Sends
from robmosys_runtime.system.activation import SystemActivation
from robmosys_runtime.system.drift import Drift
from robmosys_runtime.system.heartbeat import Heartbeat
from robmosys_runtime.system.levels import report
from robmosys_runtime.watch.watcher import Watch, watch_diagnostics
from std_srvs.srv import Trigger


def serve(executor: Executor) -> None:
    """
    Spin until the executor is shut down, through any callback that raises.

    The manager's own callbacks are :func:`guarded`; this catches what rclpy raises from
    elsewhere (a client's future, a callback of a library): the manager is never left deaf.
    """
    while True:
        try:
            executor.spin()
            return
        except Exception as error:  # noqa: B902 - reported, and spinning goes on
            say('error', f'a callback of the manager failed: {failure_text(error)}')


#: diagnostic level of each state an instance is in
_LEVELS = {'active': DiagnosticStatus.OK, 'failed': DiagnosticStatus.ERROR,
           'unknown': DiagnosticStatus.STALE}


class Manager:
    """
    The system manager: its processes, their bring-up and what operators see of them.

    Operators use three services of the node ``<system package>_bringup`` (std_srvs/Trigger):
    ``~/bring_up`` (every managed instance that is not active), ``~/bring_down``
    (deactivate, then clean up, those that came last first) and ``~/report`` (the state of
    every instance; success when all managed ones are active, or inactive where the mode
    leaves them out). The state of each instance is published on ``/diagnostics``, one
    status per instance. A managed instance that left the state the system is in is
    reported as its transition events tell (:class:`~robmosys_runtime.system.drift.Drift`),
    and no longer once it is back; with a heartbeat, one that no longer answers too. An
    instance marked ``respawn`` is started again when its process ends, and brought back.

    :param processes: the processes of this host, if started already
    :param told: the states the shared process told, if it told them before
        the manager was made (``bringup`` reads them from a pipe)
    :param groups: the processes of this host, if planned already (without
        the instances that ran before the manager started)
    """

    def __init__(self, node: Node, description: Dict[str, Any], params_file: str,
                 args: argparse.Namespace, processes: Optional[Processes] = None,
                 told: Optional[Dict[str, str]] = None,
                 groups: Optional[Groups] = None) -> None:
        self.node = node
        self.description = description
        self._args = args
        self._params_file = params_file
        self.instances = {i['instance']: i for i in description['instances']}
        #: process name -> (its instances, its command line), of the manager's host
        self.groups = groups if groups is not None else {} if args.attach else plan_processes(
            description, args.description, params_file, shared=args.processes)
        self._group_of = {n: g for g, (names, _) in self.groups.items() for n in names}
        managed = {n: i['fqn'] for n, i in self.instances.items() if i['managed']}
        self.managed = managed
        after = {n: [a for a in self.instances[n]['after'] if a in managed] for n in managed}
        timeouts = {n: float(self.instances[n]['timeout']) for n in managed
                    if self.instances[n].get('timeout')}
        # what the shared Python process of this host brings up by itself, it
        # tells on a topic too (the C++ container, only as bringup reads it)
        self.reports = Reports(
            node, description, set(managed) & set(shared_python(description, '', args.processes)),
            grace=min(GRACE, args.start_timeout), patience=args.start_timeout + args.timeout)
        if told is not None:
            # what the process told bringup before this node was made
            self.reports.told(told)
        self.activation = SystemActivation(
            node, managed, after, timeout=args.timeout, start_timeout=args.start_timeout,
            report=say, timeouts=timeouts, told=self.reports.take)
        self.stopping = threading.Event()
        #: whether the system is meant to be up (operators bring it down and up)
        self.up = True
        self._lock = threading.Lock()
        self._respawns: Dict[str, int] = {}
        self._silent: Dict[str, str] = {}
        #: started already, if given: see :func:`start_processes`
        self.processes = processes or Processes(self._exited)
        self.processes.on_exit = self._exited
        self.drift = Drift(self.activation, self.steady)
        if args.heartbeat > 0:
            heartbeat = Heartbeat(self.activation, args.heartbeat, self._silent, self.instances,
                                  set(self._group_of), self.steady, self.drift)
            threading.Thread(target=heartbeat.run, args=(self.stopping,), daemon=True,
                             name='heartbeat').start()
        #: the conformance watch, once the first bring-up is over (see _watch)
        self.watch: Optional[Watch] = None
        # the node spins already: its services and timer come last, once every
        # attribute they read is set (a report asked for at once is answered)
        self._diagnostics: Any = node.create_publisher(DiagnosticArray, '/diagnostics', 10)
        group = MutuallyExclusiveCallbackGroup()
        for service, answer in (('bring_up', self._bring_up), ('bring_down', self._bring_down),
                                ('report', self._report), ('conformance', self._conformance)):
            node.create_service(Trigger, f'~/{service}', guarded(service, answer),
                                callback_group=group)
        node.create_timer(args.diagnostics_period,
                          guarded('publishing /diagnostics', self.publish_diagnostics))

    def steady(self) -> bool:
        """Tell whether the states of the instances are the system's: up, not changing."""
        return self.up and not self.stopping.is_set()

    def start(self) -> None:
        """Start the processes of this host and bring every managed instance up."""
        started = self.processes.started()
        for group, (_, args) in self.groups.items():
            if not started:
                self.processes.start(group, args)
        self.processes.watch()
        self.activation.start()
        threading.Thread(target=self._follow, daemon=True, name='transition events').start()
        if getattr(self._args, 'check_period', 0.0) > 0:
            threading.Thread(target=self._watch, daemon=True, name='watch').start()

    def _brought_up(self) -> bool:
        """
        Wait until the first bring-up is over; return False if the manager stops first.

        The watch and the subscriptions to the instances' transition events
        are made then, not before: entities made while the instances start
        are discovered by each of their processes, and made a system of 20
        instances come up a fifth slower (issue 28).
        """
        while self.activation.running():
            if self.stopping.wait(0.05):
                return False
        return True

    def _follow(self) -> None:
        """Follow the transition events of the managed instances, once they are up."""
        if self.managed and self._brought_up():
            self.drift.follow(self.node, self.managed, self.stopping)

    def _watch(self) -> None:
        """Make the conformance watch once up, and run it (~/conformance: not compared yet)."""
        if not self._brought_up():
            return
        sends = self.processes.sends  # where the instances it started count their sends
        watch = Watch(self.node, self.description, period=self._args.check_period,
                      silence=self._args.silence, sends=Sends(sends) if sends else None,
                      started=set(self._group_of))
        self._expect(watch)
        self.watch = watch
        watch.run(self.stopping, lambda: self.drift.states_for_watch(self.states()),
                  lambda: self.steady() and not self.activation.running())

    def _expect(self, watch: Watch) -> None:
        """Tell the watch what it compares with besides the model (moded.py: the mode)."""

    # what operators see

    def states(self) -> Dict[str, str]:
        """Return the state of every instance (starting, running or exited if not managed)."""
        states = self.activation.states()
        for name in self.instances:
            if name not in self.managed:
                if name not in self._group_of:
                    states[name] = 'elsewhere'
                else:
                    states[name] = self.processes.state(self._group_of[name])
            elif name in self._silent and states.get(name) != 'failed':
                states[name] = 'unknown'
        return states

    def state_report(self) -> str:
        """Return one line per instance: its state, and why where it failed."""
        states = self.states()
        failures = self.activation.failures()
        lines = []
        for name in self.instances:
            state = states.get(name, 'starting')
            why = failures.get(name) or self._silent.get(name)
            lines.append(f'{name}: {state}' + (f' ({why})' if why else ''))
        return '\n'.join(lines)

    def publish_diagnostics(self) -> None:
        """Publish the state of every instance on /diagnostics."""
        states = self.states()
        failures = self.activation.failures()
        array = DiagnosticArray()
        array.header.stamp = self.node.get_clock().now().to_msg()
        for name, instance in self.instances.items():
            state = states.get(name, 'starting')
            level = _LEVELS.get(state, DiagnosticStatus.WARN)
            if name not in self.managed:
                level = DiagnosticStatus.ERROR if state == 'exited' else DiagnosticStatus.OK
            why = failures.get(name) or self._silent.get(name) or ''
            array.status.append(DiagnosticStatus(
                level=level, name=f"{self.description['package']}: {name}",
                message=f'{state}: {why}' if why else state, hardware_id=instance['fqn'],
                values=[KeyValue(key='state', value=state),
                        KeyValue(key='managed', value=str(instance['managed']).lower()),
                        KeyValue(key='respawns', value=str(self._respawns.get(
                            self._group_of.get(name, name), 0)))]))
        watch = self.watch
        if watch is not None:
            watch_diagnostics(watch, array)
        self._diagnostics.publish(array)

    def _bring_up(self, request: Any, response: Any) -> Any:
        with self._lock:
            self.up = True
            todo = [n for n, s in self.activation.states().items() if s != 'active']
            todo += [n for n in self.managed if n not in self.activation.states()]
            if todo and not self.activation.running():
                self.activation.start(sorted(set(todo)))
            outcome = self.activation.wait()
        response.success = outcome.ok
        response.message = report(outcome, len(self.managed))
        return response

    def _bring_down(self, request: Any, response: Any) -> Any:
        with self._lock:
            self.up = False
            self.activation.stop()
            steps = self.activation.bring_down(timeout=min(self._args.timeout, 10.0))
        response.success = True
        response.message = '\n'.join(steps)
        return response

    def _report(self, request: Any, response: Any) -> Any:
        states = self.states()
        held = self.activation.held  # the instances the system's mode leaves inactive
        response.success = all(states.get(n) == ('inactive' if n in held else 'active')
                               for n in self.managed)
        response.message = self.state_report()
        watch = self.watch
        if watch is not None:
            response.message += ''.join(
                f'\n{d.line("difference")}' for d in watch.differences.values())
        return response

    def _conformance(self, request: Any, response: Any) -> Any:
        watch = self.watch  # made by another thread, once
        differences = list(watch.differences.values()) if watch else []
        response.success = watch is not None and watch.ready and not differences
        if watch is None and getattr(self._args, 'check_period', 0.0) <= 0:
            response.message = 'the conformance watch is off (--check-period 0)'
        elif watch is None:
            response.message = 'the conformance watch starts once the system is up'
        elif not watch.ready:
            response.message = 'the conformance watch has not compared the whole system yet'
        else:
            response.message = '\n'.join(sorted(d.line() for d in differences))
        return response

    # instances that end or fall silent

    def _exited(self, group: str, code: int) -> None:
        if self.stopping.is_set():
            return
        names = self.groups[group][0]
        respawn = any(self.instances[n].get('respawn') for n in names)
        if respawn:
            self._respawns[group] = self._respawns.get(group, 0) + 1
        again = f': starting it again (respawn {self._respawns[group]})' if respawn else ''
        for name in names:
            if name in self.managed:
                self.drift.ended(name)
                self.activation.instance_failed(name, f'exited with code {code}{again}')
            else:
                say('error', f'instance {name} exited with code {code}{again}')
        if respawn:
            threading.Thread(target=self._respawn, args=(group,), daemon=True,
                             name=f'respawn {group}').start()

    def _respawn(self, group: str) -> None:
        if self.stopping.wait(self._args.respawn_delay):
            return
        names, args = self.groups[group]
        if not self.up:
            # brought down by an operator: the shared process is not to bring itself up
            args = [a for a in args if a != '--activate']
        self.processes.start(group, args)
        back = [name for name in names if name in self.managed]
        if back and self.up:
            # brought back to the state of the system, with what it held back
            self.activation.restart(*back)
