# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""
The system manager's run: ``bringup`` without ``--host`` or ``--check``.

It starts every instance (none with ``--attach``: the launch file does),
reads what the shared processes brought up by themselves, then makes the
manager's node, brings the system up, serves operators until SIGINT or
SIGTERM, and brings the system down: those that came last first.
"""

from __future__ import annotations

import argparse
from dataclasses import dataclass
import os
import signal
import threading
from typing import Any, Dict, Optional

from robmosys_runtime.hosting.output import say
from robmosys_runtime.hosting.processes import NotInstalled, plan_processes
from robmosys_runtime.hosting.running import mark
from robmosys_runtime.hosting.supervision import before_start, not_installed, Processes
from robmosys_runtime.hosting.told import (
    bringing_itself_down, read_steps, read_told, read_told_file, tellers, tells_all, told_file)
from robmosys_runtime.system.levels import Outcome, report
from robmosys_runtime.system.page import open_page, serve_page

# rclpy is imported once the instances are starting: they start it too, in
# parallel (see run_manager)


@dataclass
class Started:
    """What the start of a system's processes left for the manager."""

    #: instance -> the state its shared process told, where one tells all
    told: Optional[Dict[str, str]] = None
    #: the pipe where the shared process that brings itself down tells its steps
    steps: Optional[int] = None
    #: the group of that process
    telling: Optional[str] = None


def run_manager(description: Dict[str, Any], args: argparse.Namespace,
                params_file: str) -> int:
    """Run the system of a description with its manager; return the exit status."""
    # The instances start first: importing rclpy and making the manager's node
    # take a third of a second, which they spend starting in parallel. Their
    # exits are watched once the manager is there (Manager.start). They end
    # with the manager, even killed, and carry its mark: a manager started
    # again finds what this one left
    processes = Processes(on_exit=None, end_with_parent=True, mark=mark(
        description['package'], description.get('namespace') or '', ''),
        sends=args.check_period > 0 and not args.attach)
    signalled = threading.Event()
    manager: Optional[Any] = None

    def on_signal(signum: int, frame: Any) -> None:
        if signalled.is_set():
            # a second signal: no more waiting
            processes.kill()
            os._exit(128 + signum)
        signalled.set()
        if manager is not None:
            manager.stopping.set()

    for signum in (signal.SIGINT, signal.SIGTERM):
        signal.signal(signum, on_signal)
    try:
        # bound before anything starts: a port in use is one line, nothing started
        page = open_page(description, args)
    except OSError as error:
        say('error', f'--web {args.web}: {args.web_address}: {error.strerror or error}; '
            'nothing was started')
        return 2
    # the processes of this host are planned from it: an instance whose node
    # runs already is no process of this host's (before_start)
    local = description
    if not args.attach:
        looked = before_start(description, '', signalled.is_set)
        if looked is None:
            return 1
        if signalled.is_set():
            return 0
        local = looked
        try:
            started = start_instances(local, args, params_file, processes, signalled)
        except NotInstalled as error:
            return not_installed(error)
    elif args.told_file and tells_all(description, args.processes):
        # the launch file started the shared processes, which write the files
        started = Started(told=read_told_file(
            [told_file(args.told_file, g) for g in tellers(description, args.processes)],
            args.start_timeout + args.timeout, signalled))
    else:
        started = Started()
    managed = [i['instance'] for i in description['instances'] if i['managed']]
    printed = False
    if started.told is not None and all(started.told.get(n) == 'active' for n in managed):
        # every managed instance is up: said before this process makes a DDS
        # participant, which the instances would have discovered while they
        # were being made (issue 28)
        print(report(Outcome(active=managed), len(managed)), flush=True)
        printed = True

    import rclpy
    from rclpy.executors import MultiThreadedExecutor
    from robmosys_runtime.announce import announce_system
    from robmosys_runtime.system.manager import Manager, serve

    package = description['package']
    # The node is named by create_node, not by a __node remapping here: that
    # would rename every node of the context, the watch's too. The process's
    # own ROS arguments are its node's (launch_ros' name= renames it); the
    # helper nodes ignore them (use_global_arguments=False) and are named
    # after it (<name>_watch).
    rclpy.init(args=['bringup', *getattr(args, 'ros_args', ()),
                     '--ros-args', *description.get('ros_arguments', ())])
    # rclpy.init installed handlers that shut its context down at once: the
    # manager needs it to bring the system down
    for signum in (signal.SIGINT, signal.SIGTERM):
        signal.signal(signum, on_signal)
    node = rclpy.create_node(f'{package}_bringup',
                             namespace=description.get('namespace') or None)
    announce_system(node, package)
    executor = MultiThreadedExecutor(num_threads=4)
    executor.add_node(node)
    spinner = threading.Thread(target=serve, args=(executor,), daemon=True)
    spinner.start()
    kind = Manager
    if description.get('modes'):
        # imported here: a system without modes needs none of it
        from robmosys_runtime.system.moded import ModedManager
        kind = ModedManager
    manager = kind(node, description, params_file, args, processes, told=started.told,
                   groups={} if args.attach else plan_processes(
                       local, args.description, params_file, shared=args.processes))
    if signalled.is_set():
        manager.stopping.set()
    status = 0
    try:
        if page is not None:
            # a system with modes: the mode shown, a button for each (ModedManager)
            serve_page(page, manager, args, **getattr(manager, 'page_hooks', dict)())
        manager.start()
        while manager.activation.running() and not signalled.wait(0.02):
            pass
        if not signalled.is_set():
            outcome = manager.activation.wait()
            if not printed or not outcome.ok:
                # those the mode leaves inactive are not counted
                total = len(manager.managed) - len(manager.activation.held)
                print(report(outcome, total), flush=True)
            if not outcome.ok:
                status = 1
                if args.exit_on_failure:
                    signalled.set()
                    manager.stopping.set()
        while not signalled.wait(0.5):
            pass
        manager.activation.stop()
        if started.steps is not None and started.telling is not None:
            manager.processes.interrupt(started.telling)
            for level, text in read_steps(started.steps, wait=min(args.timeout, 10.0)):
                say(level, text)
        elif not args.attach:
            for step in manager.activation.bring_down(timeout=min(args.timeout, 10.0)):
                print(f'bringup: {step}', flush=True)
    finally:
        if page is not None:
            page.close()
        ended = manager.processes.stop()
        if started.steps is not None:
            os.close(started.steps)
        # nothing makes clients on the node any more, before it goes
        manager.activation.close()
        if getattr(manager, 'modes', None) is not None:
            manager.modes.close()  # type: ignore[attr-defined]  # a ModedManager's
        executor.shutdown()
        # a thread still in rcl when the process ends aborts it ("terminate called
        # without an active exception"): the spinning thread ends first
        spinner.join(10)
        node.destroy_node()
        rclpy.try_shutdown()
    if not ended:
        # a process that needed SIGKILL: the system did not come down cleanly
        return 1
    return status if args.exit_on_failure else 0


def start_instances(description: Dict[str, Any], args: argparse.Namespace, params_file: str,
                    processes: Processes, signalled: threading.Event) -> Started:
    """
    Start the processes of every instance; return what the shared ones told.

    The shared processes that bring up every managed instance tell them
    through pipes, read here, before this process makes a DDS participant.
    Raises :class:`NotInstalled`, with nothing started.
    """
    pipes = {group: os.pipe() for group in tellers(description, args.processes)} \
        if tells_all(description, args.processes) else {}
    try:
        groups = plan_processes(description, args.description, params_file,
                                shared=args.processes,
                                report_fds={g: w for g, (_, w) in pipes.items()})
    except NotInstalled:
        for pipe in pipes.values():
            os.close(pipe[0])
            os.close(pipe[1])
        raise
    for group, (_, command_line) in groups.items():
        processes.start(group, command_line,
                        pass_fds=[pipes[group][1]] if group in pipes else [])
    for _, writing in pipes.values():
        os.close(writing)
    started = Started(telling=bringing_itself_down(description, args.processes))
    if started.telling is not None:
        started.steps = pipes[started.telling][0]
    if pipes:
        started.told = read_told(
            [r for r, _ in pipes.values()], args.start_timeout + args.timeout, signalled,
            keep_open=[started.steps] if started.steps is not None else [])
    return started
