# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""
Run a whole system in the foreground, without ros2 launch: ``ros2 run <system> bringup``.

The system package installs a description of its instances (``bringup.json``:
package, executable, node name, namespace, remappings, whether it is managed and
what it comes after) and a ``bringup`` executable that calls :func:`main`. It
reads the options, applies the launch arguments among them to the description,
and runs one of three ways: the system with its manager
(:func:`~robmosys_runtime.system.run.run_manager`: it starts every instance,
brings the managed ones up, reports which are active, which failed and why,
which are held back by which failure; on SIGINT or SIGTERM it deactivates and
cleans them up, those that came last first, stops the processes and exits 0, 1
if one needed SIGKILL; a second signal ends it at once), a host's part
(``--host``, :func:`~robmosys_runtime.system.host.run_host`), or the running
system compared with its model once (``--check``).
While it runs, :class:`~robmosys_runtime.system.manager.Manager` offers operators
services and ``/diagnostics``, starts instances marked ``respawn`` again, and
with ``--heartbeat`` notices a managed instance that stops answering.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import re
import sys
from typing import Any, Callable, Dict, List, NoReturn, Optional, Sequence, Tuple

from ament_index_python.packages import get_package_share_directory
from robmosys_runtime.hosting.output import say
from robmosys_runtime.system.host import run_host
from robmosys_runtime.system.run import run_manager
from robmosys_runtime.tools.arguments import (
    any_given, ArgumentError, ARGUMENTS, chosen_mode, log_level, moved_description, node_values,
    normalized_namespace, ros_args_only, sim_time, temporary, without_ros_args, written)
from robmosys_runtime.tools.locations import resolve_locations
from robmosys_runtime.web.server import add_options as add_web_options


def main(description_file: str, argv: Optional[Sequence[str]] = None) -> int:
    """Run the system of a description; return the exit status."""
    # ros2 launch may hand the manager ROS arguments: they are its node's
    # (launch_ros' name= is a __node remapping), which rclpy reads
    argv = list(sys.argv[1:] if argv is None else argv)
    args = options(description_file).parse_args(without_ros_args(argv))
    args.ros_args = ros_args_only(argv)
    with open(args.description, encoding='utf-8') as stream:
        description = resolve_locations(json.load(stream))
    package = description['package']
    params_file = os.path.join(get_package_share_directory(package), description['params_file'])
    try:
        description, params_file = apply_arguments(description, params_file, args)
    except ArgumentError as error:
        # an operator's file: the line of each mistake first, as check_params prints it
        for line in getattr(error, 'lines', ()):
            print(line, file=sys.stderr, flush=True)
        say('error', f'{error}; nothing was started')
        return 2
    if args.host:
        return run_host(description, args, params_file)
    if args.check:
        return check(description, args)
    return run_manager(description, args, params_file)


class _Parser(argparse.ArgumentParser):
    """bringup's options: a bad one is one line, as a bad value of the launch arguments is."""

    def error(self, message: str) -> NoReturn:
        """Say what is wrong in one line (--help lists the options); exit 2."""
        # argparse says 'argument --timeout: 0: ...': the option and its value, as given
        said = re.sub(r'^argument (\S+): ', r'\1 ', message)
        say('error', f'{said}; nothing was started')
        raise SystemExit(2)


#: the most seconds (or periods) an option takes: rclpy's timers and Python's waits
#: hold about 292 years (int64 nanoseconds, threading.TIMEOUT_MAX); 1e9 s is 31 years
MOST = 1e9


def number(least: float = 0.0, *, above: bool = False,
           off: bool = False) -> Callable[[str], float]:
    """
    Return the type of a numeric option: a finite number from least (or above it) to MOST.

    :param off: 0 turns what the option sets off: say so when the value is below
    """
    def read(text: str) -> float:
        try:
            value = float(text)
        except ValueError:
            value = math.nan
        if math.isnan(value):
            raise argparse.ArgumentTypeError(f'{text}: is not a number')
        if value > MOST:
            raise argparse.ArgumentTypeError(f'{text}: is too large (at most 1e9)')
        if above and value <= least:
            raise argparse.ArgumentTypeError(f'{text}: is not above {least:g}')
        if value < least:
            raise argparse.ArgumentTypeError(
                f"{text}: is below {least:g}{' (0: off)' if off else ''}")
        return value
    return read


def options(description_file: str) -> argparse.ArgumentParser:
    """Return the parser of bringup's options; each numeric one refuses what is out of range."""
    parser = _Parser(
        prog='bringup', description='Start the system, bring it up, bring it down on Ctrl-C.')
    parser.add_argument('--timeout', type=number(above=True), default=30.0,
                        help='seconds for each lifecycle transition of an instance, where '
                        'the model does not set it')
    parser.add_argument('--start-timeout', type=number(above=True), default=60.0,
                        help='seconds for the process of each instance to offer its '
                        'lifecycle services')
    parser.add_argument('--exit-on-failure', action='store_true',
                        help='bring the system down and exit 1 if an instance fails to come '
                        'up (default: stay up and report)')
    parser.add_argument('--heartbeat', type=number(off=True), default=0.0, metavar='SECONDS',
                        help='ask every managed instance for its state this often, and '
                        'report one that does not answer or is no longer active (0: off)')
    parser.add_argument('--respawn-delay', type=number(), default=1.0, metavar='SECONDS',
                        help='seconds before an instance marked respawn is started again')
    parser.add_argument('--diagnostics-period', type=number(above=True), default=1.0,
                        metavar='SECONDS',
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
    parser.add_argument('--check-period', type=number(off=True), default=1.0, metavar='SECONDS',
                        help='compare the running system with its model this often, and '
                        'report each difference when it appears and when it clears (0: off)')
    parser.add_argument('--silence', type=number(above=True), default=5.0, metavar='PERIODS',
                        help='report a push port of a periodic activity that sent nothing '
                        'for this many periods of its activity while its instance is active')
    parser.add_argument('--check', action='store_true',
                        help='start nothing: compare the system running now with its model '
                        'once, print each difference at its line of the model, exit 1 if '
                        'there is one')
    parser.add_argument('--check-wait', type=number(), default=10.0, metavar='SECONDS',
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
    parser.add_argument('--mode', default='', metavar='NAME', help=ARGUMENTS['mode'][1] + (
        '; with --check: the mode to compare with (default: the one the system is in)'))
    add_web_options(parser)
    parser.add_argument('--description', default=description_file, help=argparse.SUPPRESS)
    return parser


def apply_arguments(description: Dict[str, Any], params_file: str,
                    args: argparse.Namespace) -> Tuple[Dict[str, Any], str]:
    """
    Return the description and the parameter file for the options of the launch arguments.

    With --namespace, every name of the description is moved, and the moved
    description is written to a file of its own for the processes that read
    it (``args.description``); the parameter file is the system's, or one
    made for --namespace, --use-sim-time and --params-file. The operator's
    file is checked first, as check_params checks it: its warnings are
    printed; its errors raise.

    :raises ArgumentError: an argument that cannot be applied (a
      :class:`~robmosys_runtime.tools.paramcheck.RefusedFile` with the lines
      of the operator's file's errors)
    """
    where = normalized_namespace(args.namespace)
    level = log_level(args.log_level)
    # --check without --mode: the mode the system runs in, which the check infers
    args.mode = chosen_mode(description, args.mode) if args.mode or not args.check else ''
    operator = os.path.expanduser(args.params_file)
    if operator and not os.path.isfile(operator):
        raise ArgumentError(f'--params-file {args.params_file!r}: no such file')
    if operator:
        # checked as check_params checks it, before anything starts: a value a node
        # refuses ended that node in a traceback (imported here: it needs yaml, which
        # a bring-up without a file does not, issue 28)
        from robmosys_runtime.tools.paramcheck import check_operator_file
        for line in check_operator_file(description, operator, where,
                                        argument='--params-file'):
            print(line, file=sys.stderr, flush=True)
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


def check(description: Dict[str, Any], args: argparse.Namespace) -> int:
    """Compare the running system with its model once; print each difference; 1 if any."""
    from robmosys_runtime.watch.check import check_once
    notes: List[str] = []
    differences = check_once(description, wait=args.check_wait, silence=args.silence,
                             mode=args.mode, notes=notes)
    for note in notes:
        print(note, flush=True)
    for difference in sorted(differences, key=lambda d: (d.location, d.message)):
        print(difference.line(), flush=True)
    return 1 if differences else 0
