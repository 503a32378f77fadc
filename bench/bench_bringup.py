# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""Benchmark 4: how long a system takes to come up, against its slowest single instance.

Builds one system of Python components with colcon in a temporary workspace:
``--sizes`` (largest) instances, half of them publishers at 10 Hz, half
subscribers, wired in pairs. ``ros2 run <system> bringup`` (the system manager of
robmosys_runtime) then brings up, in alternation and in the same run:

- each single instance alone (a publisher, a subscriber): the slowest of them is
  the reference, what a bring-up can at best cost;
- the first N instances of the system, for each N of ``--sizes``, with one process
  per instance and with the Python instances sharing one process
  (``processes: shared``).

Each time is from the start of ``bringup`` to its report that every managed
instance is active. Prints each time / the slowest single instance's, the
ratio issue 16 and issue 14 set the goal for (within 1.5x at 20 and at 50).
In the same rounds, the floor of each size (``bringup_floor.py``): the same
nodes made and activated in one process by rclpy's own transitions, with no
manager, no service and no discovery, from the start of that process; each
bring-up is also printed against it, which is what the manager adds.
Then ``--hang-runs`` bring-ups in a row of the system of ``--hang-size`` instances,
each with a timeout: how many came up, failed, or hung.

    make bench-bringup                    # or: .venv/bin/python bench/bench_bringup.py
"""

from __future__ import annotations

import argparse
import json
import os
from pathlib import Path
import signal
import subprocess
import sys
import tempfile
import time
from typing import IO, Sequence

import yaml

from bench_runtime import build
from benchlib import best, print_end, print_machine, ratio, spread, table
from colcon_robmosys.devtools import ros_env

SYSTEM = 'bench_bringup_system'
#: makes and activates a system's nodes in one process, with no manager
FLOOR = Path(__file__).resolve().parent / 'bringup_floor.py'
#: the "processes" of the floor's cases
FLOOR_LAYOUT = 'one, no manager (floor)'
METADATA = {'license': 'Apache-2.0',
            'maintainers': [{'name': 'Benchmark Team', 'email': 'bench@example.com'}]}
BEAT = {
    'name': 'Beat', 'package': 'bench_beat', 'language': 'python',
    'ports': {'pBeat': {'pattern': 'push', 'role': 'provided', 'type': 'std_msgs/msg/Header'}},
    'activities': {'Publish': {'period': 0.1, 'functions': ['fPublish']}},
    'functions': {'fPublish': {'code': 'self.pBeat.publish(Header(frame_id="beat"))\n'}},
}
HEAR = {
    'name': 'Hear', 'package': 'bench_hear', 'language': 'python',
    'ports': {'rBeat': {'pattern': 'push', 'role': 'required', 'type': 'std_msgs/msg/Header'}},
    'activities': {'Receive': {'trigger': 'rBeat', 'functions': ['fReceive']}},
    'functions': {'fReceive': {'code': 'self.heard = getattr(self, "heard", 0) + 1\n'}},
}


def write_workspace(src: Path, instances: int) -> None:
    """Write the two components and a system of ``instances`` instances (pairs)."""
    for model in (BEAT, HEAR):
        path = src / str(model['package']) / 'robmosys.yaml'
        path.parent.mkdir(parents=True)
        path.write_text(yaml.safe_dump({'robmosys': 1, 'defaults': METADATA,
                                        'components': [model]}, sort_keys=False))
    pairs = (instances + 1) // 2
    system = {
        'package': SYSTEM,
        'instances': {**{f'beat_{i}': {'component': 'bench_beat'} for i in range(pairs)},
                      **{f'hear_{i}': {'component': 'bench_hear'} for i in range(pairs)}},
        'connections': [{'from': f'beat_{i}.pBeat', 'to': f'hear_{i}.rBeat'}
                        for i in range(pairs)]}
    path = src / SYSTEM / 'robmosys.yaml'
    path.parent.mkdir(parents=True)
    path.write_text(yaml.safe_dump({'robmosys': 1, 'defaults': METADATA,
                                    'systems': [system]}, sort_keys=False))


def subset(install: Path, names: Sequence[str], dest: Path) -> Path:
    """Write the system's description with some instances only; return its path."""
    description = json.loads((install / SYSTEM / 'share' / SYSTEM / 'bringup.json').read_text())
    description['instances'] = [i for i in description['instances'] if i['instance'] in names]
    description['connections'] = []
    dest.write_text(json.dumps(description))
    return dest


def bring_up(install: Path, description: Path, layout: str, count: int,
             timeout: float) -> tuple[str, float]:
    """
    Bring a system up and down once; return the outcome and the seconds it took to come up.

    The outcome is ``up``, ``failed`` (bringup reported a failure), ``hung``
    (no report within timeout: bringup reports by ``--start-timeout`` plus two
    transition timeouts at the latest) or ``stuck`` (not ended within
    ``BRING_DOWN_BOUND`` of SIGINT, which bringup's own timeouts bound: the
    bring-down hung). Whatever a killed bringup left running is killed.
    """
    env = ros_env.workspace_env(install, ros_env.loopback_env(ros_env.free_domain_id()))
    executable = install / SYSTEM / 'lib' / SYSTEM / 'bringup'
    done = f'bringup: {count} of {count} managed instances active'
    with tempfile.TemporaryFile() as log:
        start = time.monotonic()
        process = subprocess.Popen(
            [sys.executable, str(executable), '--description', str(description),
             f'--{layout}', '--timeout', '30', '--start-timeout', '90'],
            env=env, stdout=log, stderr=subprocess.STDOUT, stdin=subprocess.DEVNULL,
            start_new_session=True)
        outcome, took = 'hung', timeout
        try:
            outcome, took, _ = _watch(log, process, start, timeout, done,
                                      'managed instances active')
        finally:
            if process.poll() is None:
                os.killpg(process.pid, signal.SIGINT)
                try:
                    # bringup's own bound: deactivate and cleanup (30 s each at
                    # most), then 10 s for the processes to end
                    process.wait(BRING_DOWN_BOUND)
                except subprocess.TimeoutExpired:
                    os.killpg(process.pid, signal.SIGKILL)
                    process.wait()
                    outcome = 'stuck'
            _kill_left_over(install)
    return outcome, took


def floor(install: Path, description: Path, count: int, timeout: float) -> tuple[str, float]:
    """
    Make and activate a system's nodes with no manager; return the outcome and the seconds.

    The time is from the start of the process to its report, as for bring_up.
    """
    env = ros_env.workspace_env(install, ros_env.loopback_env(ros_env.free_domain_id()))
    params = install / SYSTEM / 'share' / SYSTEM / json.loads(description.read_text())[
        'params_file']
    done = f'floor: {count} of {count} active'
    with tempfile.TemporaryFile() as log:
        start = time.monotonic()
        process = subprocess.Popen([sys.executable, str(FLOOR), str(description), str(params)],
                                   env=env, stdout=log, stderr=subprocess.STDOUT,
                                   stdin=subprocess.DEVNULL)
        outcome, took = 'hung', timeout
        try:
            outcome, took, output = _watch(log, process, start, timeout, done)
            if outcome == 'failed':
                sys.stderr.write(output)
        finally:
            try:
                process.wait(BRING_DOWN_BOUND if outcome == 'up' else 0)
            except subprocess.TimeoutExpired:
                process.kill()
                process.wait()
    return outcome, took


def _watch(log: IO[bytes], process: subprocess.Popen[bytes], start: float, timeout: float,
           done: str, failed: str | None = None) -> tuple[str, float, str]:
    """
    Read a process's output until it says done; return the outcome, the seconds and the output.

    ``failed`` (or the process ending first) makes the outcome ``failed``; no
    word within timeout seconds of start, ``hung``.
    """
    output = ''
    while time.monotonic() - start < timeout:
        output = os.pread(log.fileno(), os.fstat(log.fileno()).st_size, 0).decode(
            errors='replace')
        if done in output:
            return 'up', time.monotonic() - start, output
        if (failed is not None and failed in output) or process.poll() is not None:
            return 'failed', time.monotonic() - start, output
        time.sleep(0.02)
    return 'hung', timeout, output


#: seconds bringup may take to bring a system down and end: two transitions of
#: --timeout 30 each, the processes' 10 s to end, and a margin
BRING_DOWN_BOUND = 2 * 30 + 10 + 20


def _kill_left_over(install: Path) -> None:
    """Kill the instances a killed bringup left (each runs in a session of its own)."""
    marker = str(install).encode()
    for entry in Path('/proc').iterdir():
        if not entry.name.isdigit():
            continue
        try:
            if marker in (entry / 'cmdline').read_bytes():
                os.kill(int(entry.name), signal.SIGKILL)
        except (OSError, ValueError):
            pass


def main(argv: Sequence[str] | None = None) -> int:
    """Run the benchmark and print its figures."""
    parser = argparse.ArgumentParser(description=__doc__.split('\n\n')[0])
    parser.add_argument('--sizes', type=int, nargs='+', default=[20, 50],
                        help='instances of the systems brought up (default: 20 50)')
    parser.add_argument('--rounds', type=int, default=3,
                        help='bring-ups of each system and layout; the fastest counts')
    parser.add_argument('--hang-runs', type=int, default=30,
                        help='bring-ups in a row of the --hang-size system (default: 30)')
    parser.add_argument('--hang-size', type=int, default=20)
    parser.add_argument('--layouts', nargs='+', choices=('per-instance', 'shared'),
                        default=['per-instance', 'shared'],
                        help='process layouts of the systems of --sizes (default: both)')
    parser.add_argument('--hang-layout', choices=('per-instance', 'shared'),
                        default='per-instance')
    parser.add_argument('--timeout', type=float, default=240.0,
                        help='seconds a bring-up may take before it counts as hung (bringup '
                        'itself reports within 90 + 2 x 30 s)')
    args = parser.parse_args(argv)
    print_machine('bring-up: N instances vs the slowest single instance, one run')
    largest = max(args.sizes + [args.hang_size])
    with tempfile.TemporaryDirectory(prefix='robmosys-bench-bringup-') as tmp:
        root = Path(tmp)
        write_workspace(root / 'src', largest)
        install = build(root)  # the same build as bench_runtime's
        names = [f'{kind}_{i}' for i in range((largest + 1) // 2) for kind in ('beat', 'hear')]
        cases: dict[tuple[str, str], tuple[Path, int]] = {
            ('single publisher', 'per-instance'): (subset(install, ['beat_0'],
                                                          root / 'beat.json'), 1),
            ('single subscriber', 'per-instance'): (subset(install, ['hear_0'],
                                                           root / 'hear.json'), 1)}
        for size in args.sizes:
            path = subset(install, names[:size], root / f'system_{size}.json')
            for layout in args.layouts:
                cases[(f'{size} instances', layout)] = (path, size)
            cases[(f'{size} instances', FLOOR_LAYOUT)] = (path, size)
        times: dict[tuple[str, str], list[float]] = {case: [] for case in cases}
        for round_ in range(args.rounds):
            order = list(cases)[::1 if round_ % 2 == 0 else -1]
            for case in order:
                path, count = cases[case]
                if case[1] == FLOOR_LAYOUT:
                    outcome, took = floor(install, path, count, args.timeout)
                else:
                    outcome, took = bring_up(install, path, case[1], count, args.timeout)
                print(f'  round {round_ + 1}, {case[0]}, {case[1]}: {outcome} in {took:.2f} s',
                      flush=True)
                if outcome == 'up':
                    times[case].append(took)
        singles = [best(times[c]) for c in cases if c[0].startswith('single') and times[c]]
        reference = max(singles) if singles else float('nan')
        rows = [(name, layout, len(times[(name, layout)]),
                 f'{best(times[(name, layout)]):.2f}' if times[(name, layout)] else '-',
                 ratio(best(times[(name, layout)]), reference) if times[(name, layout)]
                 else '-') for name, layout in cases]
        print('time to all-active / the slowest single instance')
        print(table(('system', 'processes', 'runs up', 'fastest s', 'ratio to slowest single'),
                    rows))
        print('time to all-active / the floor (the same nodes up in one process, no manager)')
        print(table(('system', 'processes', 'ratio to the floor'), [
            (name, layout, ratio(best(times[(name, layout)]),
                                 best(times[(name, FLOOR_LAYOUT)])))
            for name, layout in cases
            if layout != FLOOR_LAYOUT and times[(name, layout)]
            and times.get((name, FLOOR_LAYOUT))]))
        print('spread (s):')
        for case, samples in times.items():
            if samples:
                print(f'  {case[0]}, {case[1]}: {spread(samples)}')
        hang_path = subset(install, names[:args.hang_size], root / 'hang.json')
        outcomes: dict[str, int] = {'up': 0, 'failed': 0, 'hung': 0, 'stuck': 0}
        for _ in range(args.hang_runs):
            outcome, _ = bring_up(install, hang_path, args.hang_layout, args.hang_size,
                                  args.timeout)
            outcomes[outcome] += 1
        print(f'{args.hang_runs} bring-ups in a row of {args.hang_size} instances '
              f'({args.hang_layout}): {outcomes["up"]} up, {outcomes["failed"]} failed, '
              f'{outcomes["hung"]} hung (timeout {args.timeout:g} s), {outcomes["stuck"]} '
              'stuck at bring-down')
    print_end()
    return 0


if __name__ == '__main__':
    raise SystemExit(main())
