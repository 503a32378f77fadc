# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""Build test_workspace with colcon and run one of its systems.

`make demo` runs this with the venv's Python (the publisher/subscriber
system; `--system dummy_robot_bringup` runs the dummy robot). launch_ros is
not on PyPI, so the system is brought up the way its generated launch.py
describes: the same executables, node names, remappings and parameter file,
then configured and activated through the nodes' lifecycle services in the
order of activate.py, which leaves unmanaged instances alone.
"""

from __future__ import annotations

import argparse
import contextlib
from pathlib import Path
import sys
import time

from colcon_robmosys.devtools import ros_env
from colcon_robmosys.devtools.system import (
    activate_launch_file, activation_waves, LifecycleDriver, nodes_launch_file,
    read_activate_after, read_launch_file)

REPO = Path(__file__).resolve().parent.parent

WORKSPACE = REPO / 'test_workspace'


def build(domain_id: int) -> None:
    """Build the workspace in place, showing colcon's output."""
    print(f'==> colcon build in {WORKSPACE.relative_to(REPO)}', flush=True)
    env = ros_env.loopback_env(domain_id)
    result = ros_env.run([str(Path(sys.prefix) / 'bin' / 'colcon'), 'build'],
                         env=env, cwd=WORKSPACE, timeout=1200)
    print(result.stdout, result.stderr, sep='', end='', flush=True)
    if result.returncode:
        sys.exit(f'colcon build failed with exit code {result.returncode}')


def run_system(system: str, domain_id: int, seconds: float) -> None:
    """Start the system's nodes, activate them and show what they print."""
    install = WORKSPACE / 'install'
    share = install / system / 'share' / system
    nodes = read_launch_file(nodes_launch_file(share), share)
    by_name = {node.name: node for node in nodes}
    managed = activation_waves(read_activate_after(activate_launch_file(share)))
    env = ros_env.workspace_env(install, ros_env.loopback_env(domain_id))
    print(f'==> starting {system} (ROS_DOMAIN_ID={domain_id}, DDS on loopback)')
    with contextlib.ExitStack() as stack:
        processes = {}
        for node in nodes:
            print('    ' + ' '.join(node.command(install)))
            processes[node.name] = stack.enter_context(
                ros_env.background(node.command(install), env=env))
        driver = stack.enter_context(LifecycleDriver(domain_id))
        order = [by_name[name] for wave in managed for name in wave]
        for transition in ('configure', 'activate'):
            for node in order:
                ok = driver.transition(node.fqn, transition)
                print(f'==> {transition} {node.fqn}: {"ok" if ok else "FAILED"}')
                if not ok:
                    sys.exit(f'{node.fqn} failed to {transition}')
        print(f'==> running for {seconds:g} s', flush=True)
        time.sleep(seconds)
        for node in reversed(order):
            driver.transition(node.fqn, 'deactivate')
        for name, process in processes.items():
            print(f'==> output of {name}')
            print(process.output(), end='', flush=True)


def main() -> None:
    """Build, then run."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--seconds', type=float, default=4.0,
                        help='how long the system runs (default: 4)')
    parser.add_argument('--system', default='pubsub_system',
                        help='the system package to run (default: pubsub_system)')
    parser.add_argument('--no-build', action='store_true',
                        help='run what test_workspace/install holds')
    args = parser.parse_args()
    domain_id = ros_env.free_domain_id()
    if not args.no_build:
        build(domain_id)
    run_system(args.system, domain_id, args.seconds)


if __name__ == '__main__':
    main()
