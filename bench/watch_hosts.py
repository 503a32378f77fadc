# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""The conformance watch on a site of hosts: what the base station's link and CPU carry.

``bench_watch.py --robots N`` runs this: the system of bench_bringup.py, its
pairs of a publisher at 10 Hz and its subscriber spread over N robots (each
pair on one robot), every robot and a base station a Linux network namespace
(colcon_robmosys/devtools/netns.py, as root). Each robot runs ``bringup
--host``, the base station the manager, with the watch on and off in turn, in
the same run. Once every instance is active and the system settled, it reads
over one window the bytes the base station's link received and the manager's
CPU time, and prints the cost of the watch (on - off): on the link it is the
hosts' summaries only (issue 41: at most 10 KiB/s), where a manager that
subscribed to the robots' topics would carry each of their streams.
"""

from __future__ import annotations

import argparse
import contextlib
import json
import os
from pathlib import Path
import subprocess
import sys
import tempfile
import time
from typing import Iterator

from bench_bringup import MARKER, subset
from benchlib import best, cpu_seconds, table
from colcon_robmosys.devtools import netns, ros_env

#: what the watch may add to the base station's link, at most (issue 41)
LINK_GOAL = 10 * 1024


def placed(install: Path, system: str, size: int, robots: int, dest: Path) -> Path:
    """Write the first pairs of the system with each pair on a robot; return the file."""
    description = json.loads(subset(install, system, size, dest).read_text())
    for instance in description['instances']:
        pair = int(instance['instance'].rsplit('_', 1)[1])
        instance['host'] = f'robot{pair % robots + 1}'
    dest.write_text(json.dumps(description))
    return dest


def _received(network: netns.Network, env: dict[str, str]) -> int:
    result = network.run('base', ['cat', '/sys/class/net/eth0/statistics/rx_bytes'],
                         env, timeout=30)
    return int(result.stdout)


@contextlib.contextmanager
def _site(network: netns.Network, install: Path, system: str, description: Path,
          period: float, timeout: float) -> Iterator[tuple[subprocess.Popen[bytes], dict]]:
    """Run the robots' bringups and the manager; yield the manager once all is up."""
    base = ros_env.workspace_env(install, ros_env.loopback_env(ros_env.free_domain_id()))
    base[MARKER] = f'{os.getpid()}-{time.monotonic_ns()}'
    bringup = [sys.executable, str(install / system / 'lib' / system / 'bringup'),
               '--description', str(description), '--check-period', str(period)]
    robots = sorted(h for h in network.hosts if h != 'base')
    count = len(json.loads(description.read_text())['instances'])
    with contextlib.ExitStack() as stack:
        for robot in robots:
            stack.enter_context(network.background(
                robot, [*bringup, '--host', robot, '--shared'], network.env(robot, base)))
        env = network.env('base', base)
        manager = stack.enter_context(network.background(
            'base', [*bringup, '--start-timeout', '90'], env))
        done = f'bringup: {count} of {count} managed instances active'
        deadline = time.monotonic() + timeout
        while done not in manager.output() and time.monotonic() < deadline:
            time.sleep(0.1)
        if done not in manager.output():
            sys.stderr.write(manager.output()[-3000:])
            raise RuntimeError('the site did not come up')
        # the manager's pid: `ip netns exec` execs it
        yield manager.proc, env


def measure(network: netns.Network, install: Path, system: str, description: Path,
            period: float, *, settle: float, window: float,
            timeout: float) -> tuple[float, float] | None:
    """Return the base station's link (bytes/s received) and manager's CPU, or None."""
    try:
        with _site(network, install, system, description, period, timeout) as (manager, env):
            time.sleep(settle)
            first, cpu, at = _received(network, env), cpu_seconds(manager.pid), \
                time.monotonic()
            time.sleep(window)
            took = time.monotonic() - at
            return ((_received(network, env) - first) / took,
                    (cpu_seconds(manager.pid) - cpu) / took)
    except RuntimeError:
        return None


def run(args: argparse.Namespace, install: Path, system: str, root: Path) -> None:
    """Measure each size with the watch on and off; print the table of issue 41's goal."""
    reason = netns.unavailable_reason()
    robots, sizes, period, rounds = args.robots, args.robot_sizes, args.check_period, \
        args.rounds
    if reason:
        print(f'hosts: not measured: {reason}')
        return
    hosts = ['base', *(f'robot{n + 1}' for n in range(robots))]
    samples: dict[tuple[int, float], list[tuple[float, float]]] = {}
    with tempfile.TemporaryDirectory(prefix='robmosys-bench-hosts-') as tmp, \
            netns.Network(hosts, Path(tmp)) as network:
        for round_ in range(rounds):
            cases = [(s, p) for s in sizes for p in (period, 0.0)]
            for size, each in cases[::1 if round_ % 2 == 0 else -1]:
                path = placed(install, system, size, robots, root / f'hosts_{size}.json')
                got = measure(network, install, system, path, each, settle=args.settle,
                              window=args.window, timeout=args.timeout)
                what = f'watch every {each:g} s' if each else 'watch off'
                shown = 'not up' if got is None else \
                    f'link {got[0] / 1024:.2f} KiB/s, manager {100 * got[1]:.2f} % of one CPU'
                print(f'  round {round_ + 1}, {size} instances on {robots} robots, {what}: '
                      f'{shown}', flush=True)
                if got is not None:
                    samples.setdefault((size, each), []).append(got)
    rows = []
    for size in sizes:
        on, off = samples.get((size, period), []), samples.get((size, 0.0), [])
        if not on or not off:
            rows.append((size, '-', '-', '-', '-', 'not measured'))
            continue
        link = best([s[0] for s in on]) - best([s[0] for s in off])
        cpu = 100 * (best([s[1] for s in on]) - best([s[1] for s in off]))
        rows.append((size, f'{best([s[0] for s in off]) / 1024:.2f}',
                     f'{best([s[0] for s in on]) / 1024:.2f}', f'{link / 1024:.2f}',
                     f'{cpu:.2f}', 'met' if link <= LINK_GOAL else 'NOT met'))
    print(f"base station, {robots} robots (lowest of {rounds}): its link's KiB/s received, "
          f"the manager's CPU; goal: the watch adds at most {LINK_GOAL // 1024} KiB/s")
    print(table(('instances', 'link, watch off', f'link, watch every {period:g} s',
                 'link: the watch', "manager's CPU: the watch, %", 'goal'), rows))
