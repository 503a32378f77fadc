# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""
Several Python instances of a system in one process (``processes: shared``).

``python -m robmosys_runtime.hosting.container [--activate [--report-fd FD | --report-file FILE]]
DESCRIPTION PARAMS_FILE INSTANCE... [--ros-args ...]``
creates the node of each instance from its component's class, with the name,
namespace, remappings and parameter file the launch files would give it, and
spins them all on one executor (:func:`run_nodes`): the one the system names for
its shared processes, or the most capable one its instances need. Starting a
Python node costs most of its start-up time in the interpreter and rclpy:
one process for many instances starts a large system several times faster.

With ``--activate`` (what ``bringup`` and ``<system>.launch.py`` start, where
the system manager brings the system up) it also configures and activates
each managed instance whose predecessors (``after``) it activated itself, in
the model's order, through rclpy's own transitions, before it serves any
request, and tells the manager, in one message, which it brought to which
state (:mod:`robmosys_runtime.hosting.reports`), and with ``--report-fd`` also on
that file descriptor, one line of JSON (``bringup`` reads it from a pipe
before it makes a DDS participant of its own), or with ``--report-file`` in
that file (``<system>.launch.py`` gives the same file to the manager, and
``<file>.started`` holds the process's pid): the manager does not take each
through two transitions of the lifecycle services, nor asks each its state
(each call waiting for the service of another process to be discovered was
what the manager added to the floor, issue 28). An instance that fails a
transition here is left where it is: the manager takes it up, and reports it.

With ``--activate`` it also brings its instances down itself at SIGINT or
SIGTERM (:func:`bring_down`): deactivates, then cleans up, each, the last
activated first, before its nodes go; ``bringup`` reads each step on the
same pipe, and need not discover any lifecycle service to bring the system
down (which took 3 s right after it joined the graph, issue 28). A launch's
Ctrl-C brings the system down the same way.
"""

from __future__ import annotations

import importlib
import json
import os
import sys
from typing import Any, Callable, cast, Dict, IO, List, Optional

from rclpy.lifecycle import LifecycleNode, TransitionCallbackReturn
from rclpy.node import Node
from robmosys_runtime.hosting.processes import node_arguments
from robmosys_runtime.hosting.reports import Reporter
from robmosys_runtime.hosting.told import shared_start, write_whole
from robmosys_runtime.main import run_nodes


def node_factory(instance: Dict[str, Any], params_file: str) -> Callable[[], Node]:
    """Return what creates the node of an instance, as its own process would."""
    module_name, class_name = instance['python_class'].split(':')

    def create() -> Node:
        component = getattr(importlib.import_module(module_name), class_name)
        # node-local arguments only: a remapping of one instance is not another's
        return component(instance['name'], namespace=instance['namespace'] or None,
                         cli_args=['--ros-args', *node_arguments(instance, params_file)],
                         use_global_arguments=False)
    return create


def activate_in_order(instances: List[Dict[str, Any]], nodes: List[Node],
                      untouched: Optional[List[str]] = None) -> List[str]:
    """
    Configure and activate the managed instances whose predecessors are active here.

    ``instances`` are in activation order, each with its node. Return the
    instances made active; add to ``untouched`` the managed ones left as they
    were made (unconfigured): what they come after was not activated here.
    """
    active: List[str] = []
    for instance, node in zip(instances, nodes):
        if not instance.get('managed') or not instance.get('lifecycle', True):
            continue
        if not all(a in active for a in instance.get('after', ())):
            if untouched is not None:
                untouched.append(instance['instance'])
            continue
        # a managed instance with a lifecycle: its node is a LifecycleNode
        lifecycle = cast(LifecycleNode, node)
        if lifecycle.trigger_configure() == TransitionCallbackReturn.SUCCESS and \
                lifecycle.trigger_activate() == TransitionCallbackReturn.SUCCESS:
            active.append(instance['instance'])
    return active


def bring_up(instances: List[Dict[str, Any]], nodes: List[Node], reporter: Reporter,
             report_fd: Optional[int] = None,
             report_file: Optional[str] = None) -> Optional[IO[str]]:
    """
    Activate what can be (:func:`activate_in_order`); tell the manager the states known.

    Those activated are active, those not touched unconfigured; one that
    failed a transition is left out: the manager asks it its state. The
    states are published, and written to ``report_fd`` if given, and to
    ``report_file`` if given (whole, or not at all). Return ``report_fd`` as
    a stream, left open for :func:`bring_down`'s steps; None without it.
    """
    untouched: List[str] = []
    active = activate_in_order(instances, nodes, untouched)
    states = {**dict.fromkeys(untouched, 'unconfigured'), **dict.fromkeys(active, 'active')}
    reporter.brought_up(states)
    line = json.dumps(states) + '\n'
    stream: Optional[IO[str]] = \
        None if report_fd is None else os.fdopen(report_fd, 'w', encoding='utf-8')
    stream = _tell(stream, line)
    if report_file is not None:
        write_whole(report_file, line)
    return stream


def bring_down(instances: List[Dict[str, Any]], nodes: List[Node],
               steps: Optional[IO[str]] = None) -> None:
    """
    Deactivate, then clean up, every managed instance here, the last activated first.

    What ``bringup`` does through the lifecycle services (the model's order
    reversed), done in this process, whatever brought the instances up: one
    it finds unconfigured is left so. Each step done is written to steps, a
    line each as ``bringup`` prints it (``deactivate <instance>``, ``cleanup
    <instance>``, ``error: ...`` for a transition that failed), which is then
    closed.
    """
    for instance, node in reversed(list(zip(instances, nodes))):
        if not instance.get('managed') or not instance.get('lifecycle', True):
            continue
        lifecycle = cast(LifecycleNode, node)
        # rclpy's own reading of it (LifecycleNode.trigger_shutdown, 7.1 and 9.1)
        state = lifecycle._state_machine.current_state[1]
        name = instance['instance']
        for before, trigger, verb in (('active', lifecycle.trigger_deactivate, 'deactivate'),
                                      ('inactive', lifecycle.trigger_cleanup, 'cleanup')):
            if state != before:
                continue
            if trigger() != TransitionCallbackReturn.SUCCESS:
                now = lifecycle._state_machine.current_state[1]
                steps = _tell(steps, f'error: instance {name} could not be brought down: '
                                     f'failed to {verb} (it is {now})\n')
                break
            steps = _tell(steps, f'{verb} {name}\n')
            state = lifecycle._state_machine.current_state[1]
    if steps is not None:
        try:
            steps.close()
        except OSError:
            pass  # bringup stopped reading


def _tell(stream: Optional[IO[str]], line: str) -> Optional[IO[str]]:
    """Write a line to bringup's pipe; return the stream, None once bringup stopped reading."""
    if stream is None:
        return None
    try:
        stream.write(line)
        stream.flush()
    except OSError:
        return None  # bringup stopped reading: it asks the instances
    return stream


def main(argv: Optional[List[str]] = None) -> int:
    """Run the instances named on the command line; return the exit status."""
    started = shared_start(list(sys.argv[1:] if argv is None else argv), 'container',
                           'python_class', 'Python')
    if started is None:
        return 2
    args, description, chosen = started
    reporter = Reporter(description)
    factories = [node_factory(i, args.params_file) for i in chosen]
    executor_name = description.get('executors', {}).get('python')
    ros_args = ['container', *args.ros_arguments] if args.ros_arguments else None
    if not args.activate:
        return run_nodes(factories, executor_name=executor_name, args=ros_args)
    steps: List[Optional[IO[str]]] = []
    return run_nodes(
        factories, executor_name=executor_name, args=ros_args,
        before_spin=lambda nodes: steps.append(
            bring_up(chosen, nodes, reporter, args.report_fd, args.report_file)),
        unspun=[reporter.make],
        bring_down=lambda nodes: bring_down(chosen, nodes, steps[0] if steps else None))


if __name__ == '__main__':
    sys.exit(main())
