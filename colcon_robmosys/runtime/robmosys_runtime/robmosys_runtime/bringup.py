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
first, stops the processes and exits 0. A second signal ends it at once.
"""

from __future__ import annotations

import argparse
import json
import os
import signal
import subprocess
import sys
import threading
import time
from typing import Any, Dict, List, Optional, Sequence

from ament_index_python.packages import get_package_prefix, get_package_share_directory
import rclpy
from rclpy.executors import MultiThreadedExecutor
from robmosys_runtime.activation import Outcome, SystemActivation

#: seconds each process has to end after SIGINT, before SIGKILL
STOP_TIMEOUT = 10.0


def command(instance: Dict[str, Any], params_file: str) -> List[str]:
    """Return the command line of an instance, as launch_ros would build it."""
    executable = instance.get('command') or [os.path.join(
        get_package_prefix(instance['package']), 'lib', instance['package'],
        instance['executable'])]
    args = list(executable) + ['--ros-args', '-r', f"__node:={instance['name']}"]
    if instance['namespace']:
        args += ['-r', f"__ns:={instance['namespace']}"]
    args += ['--params-file', params_file]
    for source, target in instance['remappings']:
        args += ['-r', f'{source}:={target}']
    return args


class Processes:
    """The processes of the instances, watched: one that ends is reported."""

    def __init__(self, on_exit: Any) -> None:
        self._processes: Dict[str, subprocess.Popen[bytes]] = {}
        self._on_exit = on_exit
        self._stopping = threading.Event()
        self._watch = threading.Thread(target=self._watch_loop, daemon=True)

    def start(self, name: str, args: Sequence[str]) -> None:
        """Start an instance in a session of its own: a Ctrl-C reaches only bringup."""
        self._processes[name] = subprocess.Popen(
            list(args), stdin=subprocess.DEVNULL, start_new_session=True)

    def watch(self) -> None:
        """Start watching the processes."""
        self._watch.start()

    def _watch_loop(self) -> None:
        reported = set()
        while not self._stopping.wait(0.1):
            for name, process in list(self._processes.items()):
                code = process.poll()
                if code is not None and name not in reported:
                    reported.add(name)
                    self._on_exit(name, code)

    def stop(self, timeout: float = STOP_TIMEOUT) -> None:
        """Ask every process to end (SIGINT), then kill what is left after timeout."""
        self._stopping.set()
        for process in self._processes.values():
            if process.poll() is None:
                try:
                    os.killpg(process.pid, signal.SIGINT)
                except ProcessLookupError:
                    pass
        deadline = time.monotonic() + timeout
        for process in self._processes.values():
            try:
                process.wait(max(0.0, deadline - time.monotonic()))
            except subprocess.TimeoutExpired:
                self.kill()

    def kill(self) -> None:
        """End every process at once."""
        self._stopping.set()
        for process in self._processes.values():
            try:
                os.killpg(process.pid, signal.SIGKILL)
            except ProcessLookupError:
                pass


def report(outcome: Outcome, total: int) -> str:
    """Return the final report of a bring-up, one line per problem."""
    lines = [f'bringup: {len(outcome.active)} of {total} managed instances active']
    lines += [f'bringup: {name} failed: {why}' for name, why in sorted(outcome.failed.items())]
    lines += [f"bringup: {name} held back by {', '.join(by)}"
              for name, by in sorted(outcome.held_back.items())]
    return '\n'.join(lines)


def main(description_file: str, argv: Optional[Sequence[str]] = None) -> int:
    """Run the system of a description; return the exit status."""
    parser = argparse.ArgumentParser(
        prog='bringup', description='Start the system, bring it up, bring it down on Ctrl-C.')
    parser.add_argument('--timeout', type=float, default=30.0,
                        help='seconds for each lifecycle transition of an instance')
    parser.add_argument('--start-timeout', type=float, default=60.0,
                        help='seconds for the process of each instance to offer its '
                        'lifecycle services')
    parser.add_argument('--exit-on-failure', action='store_true',
                        help='bring the system down and exit 1 if an instance fails to come '
                        'up (default: stay up and report)')
    parser.add_argument('--description', default=description_file, help=argparse.SUPPRESS)
    args = parser.parse_args(argv)
    with open(args.description, encoding='utf-8') as stream:
        description = json.load(stream)
    package = description['package']
    params_file = os.path.join(get_package_share_directory(package), description['params_file'])
    instances = description['instances']
    managed = {i['instance']: i['fqn'] for i in instances if i['managed']}
    after = {i['instance']: [a for a in i['after'] if a in managed]
             for i in instances if i['managed']}

    signalled = threading.Event()
    rclpy.init(args=['--ros-args', '-r', f'__node:={package}_bringup'])
    node = rclpy.create_node(f'{package}_bringup')
    executor = MultiThreadedExecutor(num_threads=4)
    executor.add_node(node)
    threading.Thread(target=executor.spin, daemon=True).start()
    activation = SystemActivation(node, managed, after, timeout=args.timeout,
                                  start_timeout=args.start_timeout, report=_print)

    def on_exit(name: str, code: int) -> None:
        if signalled.is_set():
            return
        if name in managed:
            activation.instance_failed(name, f'exited with code {code}')
        else:
            _print('error', f'instance {name} exited with code {code}')

    processes = Processes(on_exit)

    def on_signal(signum: int, frame: Any) -> None:
        if signalled.is_set():
            # a second signal: no more waiting
            processes.kill()
            os._exit(128 + signum)
        signalled.set()

    for signum in (signal.SIGINT, signal.SIGTERM):
        signal.signal(signum, on_signal)
    status = 0
    try:
        for instance in instances:
            processes.start(instance['instance'], command(instance, params_file))
        processes.watch()
        activation.start()
        while activation.running() and not signalled.wait(0.2):
            pass
        if not signalled.is_set():
            outcome = activation.wait()
            print(report(outcome, len(managed)), flush=True)
            if not outcome.ok:
                status = 1
                if args.exit_on_failure:
                    signalled.set()
        while not signalled.wait(0.5):
            pass
        activation.stop()
        for step in activation.bring_down(timeout=min(args.timeout, 10.0)):
            print(f'bringup: {step}', flush=True)
    finally:
        processes.stop()
        executor.shutdown()
        node.destroy_node()
        rclpy.try_shutdown()
    return status if args.exit_on_failure else 0


def _print(level: str, text: str) -> None:
    print(f'bringup: {level}: {text}' if level == 'error' else f'bringup: {text}',
          file=sys.stderr if level == 'error' else sys.stdout, flush=True)
