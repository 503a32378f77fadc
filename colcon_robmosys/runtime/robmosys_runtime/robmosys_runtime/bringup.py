# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""
Run a whole system in the foreground, without ros2 launch: ``ros2 run <system> bringup``.

The system package installs a description of its instances (``bringup.json``:
package, executable, node name, namespace, remappings, whether it is managed and
what it comes after) and a ``bringup`` executable that calls :func:`main`. It
starts every instance, brings the managed ones up (SystemActivation), reports
which are active, which failed and why, which are held back by which failure;
on SIGINT or SIGTERM it deactivates and cleans them up, those that came last
first, stops the processes and exits 0 (1 if one needed SIGKILL). A second
signal ends it at once.
While it runs, :class:`Manager` offers operators services and ``/diagnostics``,
starts instances marked ``respawn`` again, and with ``--heartbeat`` notices a
managed instance that stops answering.
"""

from __future__ import annotations

import argparse
import json
import os
import signal
import sys
import threading
from typing import Any, Dict, Optional, Sequence, Tuple

from ament_index_python.packages import get_package_share_directory
from robmosys_runtime.arguments import (
    any_given, ArgumentError, ARGUMENTS, log_level, moved_description, node_values,
    normalized_namespace, sim_time, temporary, without_ros_args, written)
from robmosys_runtime.levels import Outcome, report
from robmosys_runtime.locations import resolve_locations
from robmosys_runtime.output import say
from robmosys_runtime.processes import NotInstalled, plan_processes
from robmosys_runtime.supervision import Processes
from robmosys_runtime.told import (
    bringing_itself_down, read_steps, read_told, read_told_file, tellers, tells_all, told_file)

# rclpy is imported once the instances are starting: they start it too, in
# parallel (see main)


def main(description_file: str, argv: Optional[Sequence[str]] = None) -> int:
    """Run the system of a description; return the exit status."""
    parser = argparse.ArgumentParser(
        prog='bringup', description='Start the system, bring it up, bring it down on Ctrl-C.')
    parser.add_argument('--timeout', type=float, default=30.0,
                        help='seconds for each lifecycle transition of an instance, where '
                        'the model does not set it')
    parser.add_argument('--start-timeout', type=float, default=60.0,
                        help='seconds for the process of each instance to offer its '
                        'lifecycle services')
    parser.add_argument('--exit-on-failure', action='store_true',
                        help='bring the system down and exit 1 if an instance fails to come '
                        'up (default: stay up and report)')
    parser.add_argument('--heartbeat', type=float, default=0.0, metavar='SECONDS',
                        help='ask every managed instance for its state this often, and '
                        'report one that does not answer or is no longer active (0: off)')
    parser.add_argument('--respawn-delay', type=float, default=1.0, metavar='SECONDS',
                        help='seconds before an instance marked respawn is started again')
    parser.add_argument('--diagnostics-period', type=float, default=1.0, metavar='SECONDS',
                        help='seconds between two publications on /diagnostics')
    parser.add_argument('--attach', action='store_true',
                        help='start no instance (ros2 launch starts them): only bring the '
                        'system up, serve operators, and on Ctrl-C end without bringing '
                        'it down (the launch ends the instances)')
    parser.add_argument('--told-file', metavar='FILE',
                        help='with --attach: the file where the shared Python process that '
                        'the launch file starts writes what it brought up (its --report-file; '
                        'the C++ container writes FILE.cpp); read before the manager makes a '
                        'DDS participant')
    parser.add_argument('--host', metavar='HOST',
                        help='start only the instances the model puts on this host, and '
                        'leave bringing them up to the manager (bringup without --host)')
    layout = parser.add_mutually_exclusive_group()
    layout.add_argument('--shared', dest='processes', action='store_true', default=None,
                        help='run the Python instances of each host in one process, '
                        'the C++ ones in one component container (the model says by '
                        'default: processes: shared)')
    layout.add_argument('--per-instance', dest='processes', action='store_false',
                        help='run every instance in a process of its own')
    parser.add_argument('--check-period', type=float, default=1.0, metavar='SECONDS',
                        help='compare the running system with its model this often, and '
                        'report each difference when it appears and when it clears (0: off)')
    parser.add_argument('--silence', type=float, default=5.0, metavar='PERIODS',
                        help='report a push port of a periodic activity that sent nothing '
                        'for this many periods of its activity while its instance is active')
    parser.add_argument('--check', action='store_true',
                        help='start nothing: compare the system running now with its model '
                        'once, print each difference at its line of the model, exit 1 if '
                        'there is one')
    parser.add_argument('--check-wait', type=float, default=10.0, metavar='SECONDS',
                        help='with --check: seconds to wait for the nodes of the model, and '
                        'at most to listen for silent ports')
    # the launch arguments of the system's launch files, with the same meaning
    parser.add_argument('--use-sim-time', nargs='?', const='true', metavar='true|false',
                        help=ARGUMENTS['use_sim_time'][1] + ' (default: as the system says; '
                        'alone: true)')
    parser.add_argument('--log-level', metavar='LEVEL', help=ARGUMENTS['log_level'][1])
    parser.add_argument('--namespace', default='', help=ARGUMENTS['namespace'][1])
    parser.add_argument('--params-file', default='', metavar='FILE',
                        help=ARGUMENTS['params_file'][1])
    parser.add_argument('--description', default=description_file, help=argparse.SUPPRESS)
    # ros2 launch may hand the manager ROS arguments: rclpy reads those
    args = parser.parse_args(without_ros_args(list(sys.argv[1:] if argv is None else argv)))
    with open(args.description, encoding='utf-8') as stream:
        description = resolve_locations(json.load(stream))
    package = description['package']
    params_file = os.path.join(get_package_share_directory(package), description['params_file'])
    try:
        description, params_file = apply_arguments(description, params_file, args)
    except ArgumentError as error:
        say('error', f'{error}; nothing was started')
        return 2
    if args.host:
        return run_host(description, args, params_file)
    if args.check:
        return check(description, args)

    # The instances start first: importing rclpy and making the manager's node
    # take a third of a second, which they spend starting in parallel. Their
    # exits are watched once the manager is there (Manager.start).
    processes = Processes(on_exit=None)
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
    told: Optional[Dict[str, str]] = None
    #: the pipe where the shared process that brings itself down tells its steps,
    #: and its group
    steps: Optional[int] = None
    telling: Optional[str] = None
    printed = False
    if not args.attach:
        # the shared processes that bring up every managed instance tell them
        # through pipes, read before this process makes a DDS participant
        pipes = {group: os.pipe() for group in tellers(description, args.processes)} \
            if tells_all(description, args.processes) else {}
        try:
            groups = plan_processes(description, args.description, params_file,
                                    shared=args.processes,
                                    report_fds={g: w for g, (_, w) in pipes.items()})
        except NotInstalled as error:
            for pipe in pipes.values():
                os.close(pipe[0])
                os.close(pipe[1])
            return not_installed(error)
        for group, (_, command_line) in groups.items():
            processes.start(group, command_line,
                            pass_fds=[pipes[group][1]] if group in pipes else [])
        for _, writing in pipes.values():
            os.close(writing)
        telling = bringing_itself_down(description, args.processes)
        if telling is not None:
            steps = pipes[telling][0]
        if pipes:
            told = read_told([r for r, _ in pipes.values()], args.start_timeout + args.timeout,
                             signalled, keep_open=[steps] if steps is not None else [])
    elif args.told_file and tells_all(description, args.processes):
        # the launch file started the shared processes, which write the files
        told = read_told_file([told_file(args.told_file, g)
                               for g in tellers(description, args.processes)],
                              args.start_timeout + args.timeout, signalled)
    managed = [i['instance'] for i in description['instances'] if i['managed']]
    if told is not None and all(told.get(n) == 'active' for n in managed):
        # every managed instance is up: said before this process makes a DDS
        # participant, which the instances would have discovered while they
        # were being made (issue 28)
        print(report(Outcome(active=managed), len(managed)), flush=True)
        printed = True

    import rclpy
    from rclpy.executors import MultiThreadedExecutor
    from robmosys_runtime.announce import announce_system
    from robmosys_runtime.manager import Manager, serve

    rclpy.init(args=['--ros-args', '-r', f'__node:={package}_bringup',
                     *description.get('ros_arguments', ())])
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
    manager = Manager(node, description, params_file, args, processes, told=told)
    if signalled.is_set():
        manager.stopping.set()
    status = 0
    try:
        manager.start()
        while manager.activation.running() and not signalled.wait(0.02):
            pass
        if not signalled.is_set():
            outcome = manager.activation.wait()
            if not printed or not outcome.ok:
                print(report(outcome, len(manager.managed)), flush=True)
            if not outcome.ok:
                status = 1
                if args.exit_on_failure:
                    signalled.set()
                    manager.stopping.set()
        while not signalled.wait(0.5):
            pass
        manager.activation.stop()
        if steps is not None and telling is not None:
            manager.processes.interrupt(telling)
            for level, text in read_steps(steps, wait=min(args.timeout, 10.0)):
                say(level, text)
        elif not args.attach:
            for step in manager.activation.bring_down(timeout=min(args.timeout, 10.0)):
                print(f'bringup: {step}', flush=True)
    finally:
        ended = manager.processes.stop()
        if steps is not None:
            os.close(steps)
        # nothing makes clients on the node any more, before it goes
        manager.activation.close()
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


def apply_arguments(description: Dict[str, Any], params_file: str,
                    args: argparse.Namespace) -> Tuple[Dict[str, Any], str]:
    """
    Return the description and the parameter file for the options of the launch arguments.

    With --namespace, every name of the description is moved, and the moved
    description is written to a file of its own for the processes that read
    it (``args.description``); the parameter file is the system's, or one
    made for --namespace, --use-sim-time and --params-file.
    """
    where = normalized_namespace(args.namespace)
    level = log_level(args.log_level)
    operator = os.path.expanduser(args.params_file)
    if operator and not os.path.isfile(operator):
        raise ArgumentError(f'--params-file {args.params_file!r}: no such file')
    description = moved_description(description, where)
    simulated = sim_time(args.use_sim_time)
    if any_given(where, simulated, operator):
        values = node_values([i['fqn'] for i in description['instances']], params_file,
                             where, simulated, operator)
        params_file = written(values)
        # the conformance watch expects the values the nodes are given
        description = dict(description, instances=[dict(i, parameters=[
            dict(p, value=values[i['fqn']].get(p['name'], p['value']))
            for p in i['parameters']]) if 'parameters' in i else i
            for i in description['instances']])
    if level:
        description = dict(description, ros_arguments=['--log-level', level])
    if where or level or operator or simulated is not None:
        args.description = temporary(json.dumps(description), 'robmosys_bringup_', '.json')
    return description, params_file


def not_installed(error: NotInstalled) -> int:
    """Report the packages that instances need and do not find; return the exit status."""
    for problem in error.problems:
        say('error', f'{problem}; nothing was started')
    return 1


def check(description: Dict[str, Any], args: argparse.Namespace) -> int:
    """Compare the running system with its model once; print each difference; 1 if any."""
    from robmosys_runtime.check import check_once
    differences = check_once(description, wait=args.check_wait, silence=args.silence)
    for difference in sorted(differences, key=lambda d: (d.location, d.message)):
        print(difference.line(), flush=True)
    return 1 if differences else 0


def run_host(description: Dict[str, Any], args: argparse.Namespace, params_file: str) -> int:
    """
    Run the instances of one host until SIGINT or SIGTERM; return the exit status.

    The manager, on its own host, brings them up with the others; instances
    marked respawn are started again here, and its heartbeat brings them back.
    """
    try:
        groups = plan_processes(description, args.description, params_file, host=args.host,
                                shared=args.processes)
    except NotInstalled as error:
        return not_installed(error)
    if not groups:
        say('error', f'no instance of the system runs on the host {args.host}')
        return 1
    stopping = threading.Event()

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

    # started from the main thread, and again from the thread that watches them
    # (exited): both live as long as this bringup, and the instances end with it
    processes = Processes(exited, end_with_parent=True)

    def start(group: str) -> None:
        processes.start(group, groups[group][1])

    def on_signal(signum: int, frame: Any) -> None:
        if stopping.is_set():
            processes.kill()
            os._exit(128 + signum)
        stopping.set()

    for signum in (signal.SIGINT, signal.SIGTERM):
        signal.signal(signum, on_signal)
    try:
        for group in groups:
            start(group)
        processes.watch()
        started = sorted(n for names, _ in groups.values() for n in names)
        say('info', f"host {args.host}: started {', '.join(started)}")
        while not stopping.wait(0.5):
            pass
    finally:
        ended = processes.stop()
    # 1: a process needed SIGKILL
    return 0 if ended else 1
