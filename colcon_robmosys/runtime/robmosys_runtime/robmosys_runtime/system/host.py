# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""
A host's part of a system: ``bringup --host HOST``.

It runs the instances the model puts on its host, starts those marked
``respawn`` again, and leaves bringing them up to the manager, which runs on
its own host (``bringup`` without ``--host``).
"""

from __future__ import annotations

import argparse
import contextlib
import os
from pathlib import Path
import signal
import threading
from typing import AbstractSet, Any, Dict, Iterator, Optional

from robmosys_runtime.hosting.output import say
from robmosys_runtime.hosting.processes import Groups, NotInstalled, plan_processes
from robmosys_runtime.hosting.running import mark
from robmosys_runtime.hosting.supervision import before_start, not_installed, Processes


def run_host(description: Dict[str, Any], args: argparse.Namespace, params_file: str) -> int:
    """
    Run the instances of one host until SIGINT or SIGTERM; return the exit status.

    The manager, on its own host, brings them up with the others; instances
    marked respawn are started again here, and its heartbeat brings them back.
    """
    if not any(i.get('host', '') == args.host for i in description['instances']):
        say('error', f'no instance of the system runs on the host {args.host}')
        return 1
    stopping = threading.Event()
    groups: Groups = {}

    def exited(group: str, code: int) -> None:
        if stopping.is_set():
            return
        names = groups[group][0]
        if any(i.get('respawn') for i in description['instances'] if i['instance'] in names):
            say('error', f"{', '.join(names)} exited with code {code}: starting it again")
            if not stopping.wait(args.respawn_delay):
                start(group)
        else:
            say('error', f"{', '.join(names)} exited with code {code}")

    # the instances end with this bringup, even killed, and carry its mark
    processes = Processes(exited, end_with_parent=True, mark=mark(
        description['package'], description.get('namespace') or '', args.host),
        sends=args.check_period > 0)

    def start(group: str) -> None:
        processes.start(group, groups[group][1])

    def on_signal(signum: int, frame: Any) -> None:
        if stopping.is_set():
            processes.kill()
            os._exit(128 + signum)
        stopping.set()

    for signum in (signal.SIGINT, signal.SIGTERM):
        signal.signal(signum, on_signal)
    # what a bringup --host of this host left is waited for; a node that runs
    # already is taken as it is (before_start)
    local = before_start(description, args.host, stopping.is_set)
    if local is None:
        return 1
    if stopping.is_set():
        return 0
    try:
        groups.update(plan_processes(local, args.description, params_file, host=args.host,
                                     shared=args.processes))
    except NotInstalled as error:
        return not_installed(error)
    try:
        for group in groups:
            start(group)
        processes.watch()
        started = sorted(n for names, _ in groups.values() for n in names)
        if started:
            say('info', f"host {args.host}: started {', '.join(started)}")
        with host_watch(description, args, stopping, processes.sends, set(started)):
            while not stopping.wait(0.5):
                pass
    finally:
        ended = processes.stop()
    # 1: a process needed SIGKILL
    return 0 if ended else 1


@contextlib.contextmanager
def host_watch(description: Dict[str, Any], args: argparse.Namespace,
               stopping: threading.Event, sends: Optional[Path] = None,
               started: AbstractSet[str] = frozenset()) -> Iterator[None]:
    """
    Watch the push ports of this host's instances for the manager, in a with block.

    Only where the watch is on (``--check-period``) and the host has such
    ports: it reads when they last sent (those of the instances it started,
    which keep the time of their sends in ``sends``) or listens to them here,
    and sends the manager a summary each check period
    (:class:`~robmosys_runtime.watch.hosts.HostSummary`), on a node
    ``<system>_<host>_bringup``.
    """
    from robmosys_runtime.watch.conformance import Model
    from robmosys_runtime.watch.hosts import names_of, summary_topic, watched_names
    model = Model(description)
    names = names_of(watched_names(model), args.host)
    if args.check_period <= 0 or not names:
        yield
        return
    import rclpy
    from rclpy.signals import SignalHandlerOptions
    from robmosys_runtime.sends import Sends
    from robmosys_runtime.watch.hosts import counted_names, HostSummary
    context = rclpy.Context()
    # SIGINT and SIGTERM stay this bringup's: it ends its processes first
    rclpy.init(context=context, args=['--ros-args', *description.get('ros_arguments', ())],
               signal_handler_options=SignalHandlerOptions.NO)
    node = rclpy.create_node(f"{description['package']}_{args.host}_bringup",
                             namespace=description.get('namespace') or None, context=context)
    summary = HostSummary(node, names, summary_topic(description), args.host,
                          args.check_period, Sends(sends) if sends else None,
                          counted_names(model, names, started))
    thread = threading.Thread(target=summary.run, args=(stopping,), daemon=True,
                              name='host watch')
    thread.start()
    try:
        yield
    finally:
        stopping.set()
        thread.join(10)
        node.destroy_node()
        context.try_shutdown()
