# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""
Several Python instances of a system in one process (``processes: shared``).

``python -m robmosys_runtime.container [--activate [--report-fd FD | --report-file FILE]]
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
state (:mod:`robmosys_runtime.reports`), and with ``--report-fd`` also on
that file descriptor, one line of JSON (``bringup`` reads it from a pipe
before it makes a DDS participant of its own), or with ``--report-file`` in
that file (``<system>.launch.py`` gives the same file to the manager, and
``<file>.started`` holds the process's pid): the manager does not take each
through two transitions of the lifecycle services, nor asks each its state
(each call waiting for the service of another process to be discovered was
what the manager added to the floor, issue 28). An instance that fails a
transition here is left where it is: the manager takes it up, and reports it.
"""

from __future__ import annotations

import importlib
import json
import os
import sys
from typing import Any, Callable, cast, Dict, List, Optional

from rclpy.lifecycle import LifecycleNode, TransitionCallbackReturn
from rclpy.node import Node
from robmosys_runtime.main import run_nodes
from robmosys_runtime.processes import node_arguments
from robmosys_runtime.reports import Reporter
from robmosys_runtime.told import shared_start, write_whole


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
             report_fd: Optional[int] = None, report_file: Optional[str] = None) -> None:
    """
    Activate what can be (:func:`activate_in_order`); tell the manager the states known.

    Those activated are active, those not touched unconfigured; one that
    failed a transition is left out: the manager asks it its state. The
    states are published, and written to ``report_fd`` if given, which is
    then closed, and to ``report_file`` if given (whole, or not at all).
    """
    untouched: List[str] = []
    active = activate_in_order(instances, nodes, untouched)
    states = {**dict.fromkeys(untouched, 'unconfigured'), **dict.fromkeys(active, 'active')}
    reporter.brought_up(states)
    line = json.dumps(states) + '\n'
    if report_fd is not None:
        try:
            with os.fdopen(report_fd, 'w', encoding='utf-8') as stream:
                stream.write(line)
        except OSError:
            pass  # bringup stopped reading: it asks the instances
    if report_file is not None:
        write_whole(report_file, line)


def main(argv: Optional[List[str]] = None) -> int:
    """Run the instances named on the command line; return the exit status."""
    started = shared_start(list(sys.argv[1:] if argv is None else argv), 'container',
                           'python_class', 'Python')
    if started is None:
        return 2
    args, description, chosen = started
    reporter = Reporter(description)
    return run_nodes([node_factory(i, args.params_file) for i in chosen],
                     executor_name=description.get('executors', {}).get('python'),
                     args=['container', *args.ros_arguments] if args.ros_arguments else None,
                     before_spin=(lambda nodes: bring_up(chosen, nodes, reporter, args.report_fd,
                                                         args.report_file))
                     if args.activate else None,
                     unspun=[reporter.make] if args.activate else ())


if __name__ == '__main__':
    sys.exit(main())
