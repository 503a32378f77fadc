# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""Benchmark P3: the CPU a listener spends per message received, generated vs hand-written.

Three listeners of the same messages (std_msgs/msg/Header from the hand-written talker
of ``handwritten_pubsub.py``, keep_last 10, reliable), each a lifecycle node in a process
of its own, on loopback DDS:

- **generated**: the listener model of ``bench_runtime.py``, built with colcon, on the
  executor its model names (events; Python's default is multi-threaded);
- **hand-written, default**: ``handwritten_pubsub.py listener default``, spun by
  ``rclpy.spin(node)`` (rclpy's SingleThreadedExecutor), as the ROS 2 tutorials write it;
- **hand-written, same executor**: the same node on the generated one's executor.

The listener runs pinned to one CPU and the talker to another (``taskset``), so that
neither shares its CPU with the other and 5 % differences are measurable. Each round
runs the three in turn, in an order that rotates from round to round; the figures are
the medians of the rounds. Three loads: 100 Hz; the highest rate the hand-written
default listener keeps up with (found first: the largest burst of messages per 10 ms
of which it receives 95 %); 10 kHz offered. The C++ listeners (generated vs
rclcpp_lifecycle by hand) are measured by ``bench_runtime.py`` where rclcpp exists.

Prints each goal of issue 28 with "met" or "NOT met".

    .venv/bin/python bench/bench_messages.py [--rounds 5] [--seconds 4]
"""

from __future__ import annotations

import argparse
import os
from pathlib import Path
import shutil
import statistics
import tempfile
from typing import Sequence

from bench_runtime import build, commands, HANDWRITTEN, LISTENER, Run, run_pair, write_models
from benchlib import print_end, print_machine, ratio, table
from colcon_robmosys.devtools import ros_env

KINDS = ('generated', 'hand-written, default', 'hand-written, same executor')
#: the executor of the generated listener: the one its model names
GENERATED_EXECUTOR = str(LISTENER['executor'])
HANDWRITTEN_EXECUTOR = {'hand-written, default': 'default',
                        'hand-written, same executor': GENERATED_EXECUTOR}
#: bursts (messages per 10 ms) tried for the highest rate the hand-written node keeps up with
BURSTS = (1, 2, 5, 10, 20, 50)
KEEPS_UP = 0.95
#: goal -> (generated / which, at most)
GOALS = {'hand-written, default': 0.8, 'hand-written, same executor': 1.0}
#: the generated listener receives this many times the messages of the default one at 10 kHz
RATE_GOAL = 3.0


def pinned(cpu: int, command: list[str]) -> list[str]:
    """Return a command that runs on one CPU only."""
    return ['taskset', '-c', str(cpu), *command]


def pair(kind: str, install: Path, burst: int, warmup: float) -> dict[str, list[str]]:
    """Return the talker and the listener of a kind, each pinned to a CPU of its own."""
    cmds = commands('generated', install, burst, warmup)
    handwritten = commands('hand-written', install, burst, warmup)
    # the hand-written talker, on the events executor: it sends the most per CPU second
    talker = handwritten['talker']
    listener = cmds['listener']
    if kind != 'generated':
        listener = handwritten['listener']
        listener[listener.index('listener') + 1] = HANDWRITTEN_EXECUTOR[kind]
    cpus = sorted(os.sched_getaffinity(0))
    return {'talker': pinned(cpus[0], talker), 'listener': pinned(cpus[-1], listener)}


def keeps_up(install: Path, base_env: dict[str, str], seconds: float, warmup: float) -> int:
    """Return the largest burst of which the hand-written default listener receives 95 %."""
    best = 1
    for burst in BURSTS:
        run = run_pair(pair('hand-written, default', install, burst, warmup), base_env, burst,
                       seconds, warmup)
        share = run.received_rate / run.sent_rate if run.sent_rate else 0.0
        print(f'  calibration: {burst} per 10 ms, {run.sent_rate:.0f}/s sent, '
              f'{run.received_rate:.0f}/s received ({share:.0%})', flush=True)
        if share < KEEPS_UP:
            break
        best = burst
    return best


def median_of(runs: list[Run], key: str) -> float:
    """Return the median of a figure over rounds."""
    return statistics.median(float(getattr(r, key)) for r in runs)


def verdict(value: float, at_most: float) -> str:
    """Return whether a ratio meets its goal."""
    return 'met' if value <= at_most else 'NOT met'


def main(argv: Sequence[str] | None = None) -> int:
    """Run the benchmark, print its figures and its goals."""
    parser = argparse.ArgumentParser(description=__doc__.split('\n\n')[0])
    parser.add_argument('--rounds', type=int, default=5,
                        help='rounds, each running the three listeners (default: 5)')
    parser.add_argument('--seconds', type=float, default=4.0,
                        help='measured seconds per run (default: 4)')
    parser.add_argument('--warmup', type=float, default=1.0,
                        help='seconds of each run not measured (default: 1)')
    parser.add_argument('--burst', type=int, default=0,
                        help='messages per 10 ms of the middle load (default: found, the '
                             'highest rate the hand-written default listener keeps up with)')
    args = parser.parse_args(argv)
    print_machine('P3: listener CPU per message received, generated vs hand-written '
                  '(Python, pinned with taskset)')
    if shutil.which('taskset') is None or len(os.sched_getaffinity(0)) < 2:
        print('skipped: needs taskset and two CPUs')
        return 0
    with tempfile.TemporaryDirectory(prefix='robmosys-bench-msg-') as tmp:
        root = Path(tmp)
        write_models(root / 'src')
        install = build(root)
        base_env = ros_env.workspace_env(install, ros_env.loopback_env(ros_env.free_domain_id()))
        burst = args.burst or keeps_up(install, base_env, 2.0, args.warmup)
        loads = {'100 Hz': 1, f'{burst * 100} Hz (kept up with)': burst,
                 '10 kHz offered': 100}
        runs: dict[tuple[str, str], list[Run]] = {}
        for round_ in range(args.rounds):
            order = KINDS[round_ % 3:] + KINDS[:round_ % 3]
            for load, messages in loads.items():
                for kind in order:
                    run = run_pair(pair(kind, install, messages, args.warmup), base_env,
                                   messages, args.seconds, args.warmup)
                    runs.setdefault((load, kind), []).append(run)
                    print(f'  round {round_ + 1}, {load}, {kind}: {run.received_rate:.0f}/s '
                          f'received, {run.cpu_per_received_us:.0f} us CPU/message',
                          flush=True)
    print(f'handwritten: {HANDWRITTEN.name}; medians of {args.rounds} rounds')
    rows, goals = [], []
    for load in loads:
        cpu = {k: median_of(runs[(load, k)], 'cpu_per_received_us') for k in KINDS}
        rate = {k: median_of(runs[(load, k)], 'received_rate') for k in KINDS}
        for kind in KINDS:
            rows.append([load, kind, f'{rate[kind]:.0f}', f'{cpu[kind]:.0f}',
                         ratio(cpu['generated'], cpu[kind]) if kind != 'generated' else '',
                         ' '.join(f'{r.cpu_per_received_us:.0f}'
                                  for r in runs[(load, kind)])])
        if load != '10 kHz offered':
            for kind, at_most in GOALS.items():
                value = cpu['generated'] / cpu[kind]
                goals.append(f'{load}: generated CPU/message <= {at_most}x of {kind}: '
                             f'{value:.2f}x: {verdict(value, at_most)}')
        else:
            value = rate['generated'] / rate['hand-written, default']
            goals.append(f'{load}: generated receives >= {RATE_GOAL}x the messages/s of '
                         f'hand-written, default: {value:.2f}x: '
                         f'{"met" if value >= RATE_GOAL else "NOT met"}')
    print(table(['load', 'listener', 'received/s', 'CPU us/message', 'generated / it',
                 'CPU us/message per round'], rows))
    print('\n'.join(goals))
    print_end()
    return 0


if __name__ == '__main__':
    raise SystemExit(main())
