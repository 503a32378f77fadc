# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""Build test_workspace with colcon and run one of its systems, as a user does.

`make demo` runs this with the venv's Python, which is the ROS 2 underlay:

1. ``colcon build`` in test_workspace;
2. ``ros2 run <system> bringup`` in the environment of the install: the system
   manager starts every instance, configures and activates them in the order of
   the model and reports. ros2cli is not on PyPI, so this runs the executable
   that ``ros2 run`` would run;
3. while the system runs, it counts the messages on every topic that the model
   connects, as ``ros2 topic hz`` would, then brings the system down with
   Ctrl-C (SIGINT), as an operator does.

It exits 0 when the build passed, every managed instance became active, every
connected topic carried a message and bringup ended by itself with 0. Every ROS 2
process keeps DDS on loopback, with a ROS_DOMAIN_ID of its own.
"""

from __future__ import annotations

import argparse
import json
import os
from pathlib import Path
import signal
import subprocess
import sys
import time

from colcon_robmosys.devtools import ros_env, workspace

REPO = Path(__file__).resolve().parent.parent

WORKSPACE = REPO / 'test_workspace'

#: seconds for each step: the build, the bring-up, the bring-down
BUILD_TIMEOUT = 1200.0
BRING_UP_TIMEOUT = 120.0
BRING_DOWN_TIMEOUT = 30.0


def say(text: str) -> None:
    """Print a line of the demo's own, apart from what colcon and the system print."""
    print(f'==> {text}', flush=True)


def run_to_end(command: list[str], *, env: dict[str, str], timeout: float,
               cwd: Path | None = None) -> int:
    """Run a command with its output on the terminal; kill it after timeout."""
    with subprocess.Popen(command, env=env, cwd=cwd, stdin=subprocess.DEVNULL,
                          start_new_session=True) as process:
        try:
            return process.wait(timeout)
        except BaseException:  # noqa: B902 - a timeout or a Ctrl-C: nothing left behind
            os.killpg(process.pid, signal.SIGKILL)
            raise


def build(distro: str, domain_id: int) -> None:
    """Build the workspace in place, showing colcon's output."""
    arguments = workspace.bases_of(distro).command('build')
    say(f'{" ".join(["colcon", *arguments])}   (in {WORKSPACE.relative_to(REPO)}, '
        f'with ROS 2 {distro.capitalize()} of {Path(sys.prefix).name})')
    code = run_to_end([str(Path(sys.prefix) / 'bin' / 'colcon'), *arguments],
                      env=ros_env.loopback_env(domain_id), cwd=WORKSPACE,
                      timeout=BUILD_TIMEOUT)
    if code:
        sys.exit(f'colcon build failed with exit code {code}')


def run(system: str, install: Path, domain_id: int, seconds: float) -> int:
    """Run the system in the environment of the install; return the exit status."""
    env = ros_env.workspace_env(install, ros_env.loopback_env(domain_id))
    command = [sys.executable, __file__, '--run-system', system, '--seconds', str(seconds)]
    return run_to_end(command, env=env,
                      timeout=BRING_UP_TIMEOUT + seconds + BRING_DOWN_TIMEOUT + 30)


def run_system(system: str, seconds: float) -> int:
    """Start the system's bringup, count its messages, bring it down; return the status.

    This runs in the environment of the install (see :func:`run`), so that the
    system's message packages and robmosys_runtime import here.
    """
    from ament_index_python.packages import (
        get_package_prefix, get_package_share_directory, PackageNotFoundError)
    from robmosys_runtime.tools.smoke import (
        interface, Probe, spinning_node, stop, TOPIC_ENTITIES, wait_until_up)

    try:
        share = Path(get_package_share_directory(system))
    except PackageNotFoundError:
        print(f'demo: error: the install has no package {system!r}', file=sys.stderr)
        return 1
    if not (share / 'bringup.json').is_file():
        print(f'demo: error: {system!r} is not a system package (it has no bringup.json)',
              file=sys.stderr)
        return 1
    with open(share / 'bringup.json', encoding='utf-8') as stream:
        description = json.load(stream)
    bringup = Path(get_package_prefix(system)) / 'lib' / system / 'bringup'
    say(f'ros2 run {system} bringup   (ROS_DOMAIN_ID={os.environ["ROS_DOMAIN_ID"]}, '
        f'DDS on loopback; this runs {bringup.relative_to(REPO)})')
    topics = {c['name']: c['type'] for c in description['connections']
              if c['entity'] in TOPIC_ENTITIES}
    problems: list[str] = []
    with spinning_node('demo_topic_counter') as node:
        manager = subprocess.Popen([str(bringup)], stdin=subprocess.DEVNULL,
                                   start_new_session=True)
        try:
            probe = Probe(node)
            for topic, type_name in topics.items():
                probe.listen(topic, interface(type_name))
            not_up = wait_until_up(probe, description, manager, BRING_UP_TIMEOUT)
            if not_up:
                problems.append(not_up)
            else:
                say(f'the system is up: running for {seconds:g} s')
                before = {topic: probe.received(topic) for topic in topics}
                time.sleep(seconds)
                for topic, type_name in topics.items():
                    count = probe.received(topic) - before[topic]
                    say(f'{count} messages received in {seconds:g} s on {topic} '
                        f'({type_name})')
                    if probe.received(topic) == 0:
                        problems.append(f'no message on {topic}')
        finally:
            if manager.poll() is None:
                say('Ctrl-C (SIGINT) to bringup: the system comes down')
            else:
                problems.append(f'bringup exited early with code {manager.returncode}')
            problems += stop(manager, BRING_DOWN_TIMEOUT)
    for problem in problems:
        print(f'demo: error: {problem}', file=sys.stderr, flush=True)
    if not problems:
        say(f'{system} came up, carried data on each of its {len(topics)} connected topics '
            'and came down cleanly')
    return 1 if problems else 0


def main() -> int:
    """Build, then run."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--seconds', type=float, default=4.0,
                        help='how long the system runs once it is up (default: 4)')
    parser.add_argument('--system', default='pubsub_system',
                        help='the system package to run (default: pubsub_system; '
                        'dummy_robot_bringup is the ROS 2 dummy robot)')
    parser.add_argument('--distro', default=workspace.venv_distribution(),
                        choices=workspace.DISTRIBUTIONS,
                        help="the ROS 2 distribution of this venv (make's ROS_DISTRO; "
                        'default: that of its ros-* wheels): jazzy builds into '
                        'build-jazzy/ and install-jazzy/')
    parser.add_argument('--no-build', action='store_true',
                        help='run what the install of test_workspace holds')
    parser.add_argument('--run-system', metavar='SYSTEM', help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.run_system:
        return run_system(args.run_system, args.seconds)
    domain_id = ros_env.free_domain_id()
    if not args.no_build:
        build(args.distro, domain_id)
    install = WORKSPACE / workspace.bases_of(args.distro).install
    return run(args.system, install, domain_id, args.seconds)


if __name__ == '__main__':
    sys.exit(main())
