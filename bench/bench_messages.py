# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""Benchmark P3: the CPU a listener spends per message received, generated vs hand-written.

Per language, three listeners of the same messages (std_msgs/msg/Header from a
hand-written talker on the events executor, keep_last 10, reliable), each a lifecycle
node in a process of its own, on loopback DDS:

- **generated**: the listener model of ``bench_runtime.py`` (Python, or its C++ twin with
  the user code of ``generated_cpp/``), built with colcon, on the executor its model names
  (events; Python's default is multi-threaded);
- **hand-written, default**: spun as the ROS 2 tutorials write it: ``rclpy.spin(node)``
  (``handwritten_pubsub.py listener default``) or
  ``rclcpp::spin(node->get_node_base_interface())`` (``handwritten_cpp``'s
  ``pubsub listener default``), the SingleThreadedExecutor of rclpy or rclcpp;
- **hand-written, same executor**: the same node on the generated one's executor.

The listener runs pinned to one CPU and the talker to another (``taskset``), so that
neither shares its CPU with the other and 5 % differences are measurable. Each round
runs the three in turn, in an order that rotates from round to round; the figures are
the medians of the rounds. Three loads: 100 Hz; the highest rate the hand-written
default listener keeps up with (found first, per language: the largest burst of messages
per 10 ms of which it receives 95 %); 10 kHz offered. C++ needs rclcpp,
rclcpp_lifecycle and rclcpp_components (not on PyPI): by default it runs where they are
found (``bench_runtime.cpp_skip_reason``) and is skipped, with the reason, elsewhere.

Prints each goal of issue 28 with "met" or "NOT met".

    .venv/bin/python bench/bench_messages.py [--rounds 5] [--seconds 4] [--languages cpp]
"""

from __future__ import annotations

import argparse
from dataclasses import dataclass
import os
from pathlib import Path
import shutil
import statistics
from typing import Sequence

from bench_runtime import commands, cpp_skip_reason, HANDWRITTEN, HANDWRITTEN_CPP
from bench_runtime import LISTENER, pairs_workspace, Run, run_pair
from benchlib import print_end, print_machine, ratio, table
from colcon_robmosys.devtools import ros_env

KINDS = ('generated', 'hand-written, default', 'hand-written, same executor')
#: the executor of the generated listener: the one its model names (the same in C++)
GENERATED_EXECUTOR = str(LISTENER['executor'])
HANDWRITTEN_EXECUTOR = {'hand-written, default': 'default',
                        'hand-written, same executor': GENERATED_EXECUTOR}
#: the talker's executor: the one that sends the most per CPU second
TALKER_EXECUTOR = 'events'
KEEPS_UP = 0.95
OFFERED = 100  # messages per 10 ms: 10 kHz


@dataclass(frozen=True)
class Language:
    """What differs between the Python half of P3 and its C++ half."""

    title: str
    #: the kinds of pair of bench_runtime.commands: the generated one, the hand-written one
    generated: str
    handwritten: str
    #: the source of the hand-written nodes, as the report names it
    source: str
    #: hand-written kind -> the most the generated listener's CPU/message may be of its
    goals: dict[str, float]
    #: bursts (messages per 10 ms) tried for the highest rate the default node keeps up with
    bursts: tuple[int, ...]
    #: the generated listener receives at least this many times the messages/s of the
    #: default one at 10 kHz offered (None: no such goal)
    rate_goal: float | None


LANGUAGES = {
    'python': Language('Python', 'generated', 'hand-written', HANDWRITTEN.name,
                       {'hand-written, default': 0.8, 'hand-written, same executor': 1.0},
                       (1, 2, 5, 10, 20, 50), 3.0),
    'cpp': Language('C++', 'generated C++', 'hand-written C++',
                    f'{HANDWRITTEN_CPP.name}/src/pubsub.cpp',
                    {'hand-written, default': 0.9, 'hand-written, same executor': 1.02},
                    (1, 2, 5, 10, 20, 50, OFFERED), None),
}


def pinned(cpu: int, command: list[str]) -> list[str]:
    """Return a command that runs on one CPU only."""
    return ['taskset', '-c', str(cpu), *command]


def with_executor(command: list[str], role: str, executor: str) -> list[str]:
    """Return a hand-written node's command with its executor (the argument after its role)."""
    command = list(command)
    command[command.index(role) + 1] = executor
    return command


def pair(language: Language, kind: str, install: Path, burst: int, warmup: float
         ) -> dict[str, list[str]]:
    """Return the talker and the listener of a kind, each pinned to a CPU of its own."""
    handwritten = commands(language.handwritten, install, burst, warmup)
    talker = with_executor(handwritten['talker'], 'talker', TALKER_EXECUTOR)
    if kind == 'generated':
        listener = commands(language.generated, install, burst, warmup)['listener']
    else:
        listener = with_executor(handwritten['listener'], 'listener',
                                 HANDWRITTEN_EXECUTOR[kind])
    cpus = sorted(os.sched_getaffinity(0))
    return {'talker': pinned(cpus[0], talker), 'listener': pinned(cpus[-1], listener)}


def keeps_up(language: Language, install: Path, base_env: dict[str, str], seconds: float,
             warmup: float) -> int:
    """Return the largest burst of which the hand-written default listener receives 95 %."""
    best = 1
    for burst in language.bursts:
        run = run_pair(pair(language, 'hand-written, default', install, burst, warmup),
                       base_env, burst, seconds, warmup)
        share = run.received_rate / run.sent_rate if run.sent_rate else 0.0
        print(f'  {language.title} calibration: {burst} per 10 ms, {run.sent_rate:.0f}/s sent, '
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


def loads_of(burst: int) -> dict[str, int]:
    """Return the loads measured, label -> messages per 10 ms (10 kHz once only)."""
    loads = {'100 Hz': 1, f'{burst * 100} Hz (kept up with)': burst}
    if burst != OFFERED:
        loads['10 kHz offered'] = OFFERED
    return loads


def measure(language: Language, install: Path, base_env: dict[str, str],
            args: argparse.Namespace) -> tuple[dict[str, int], dict[tuple[str, str], list[Run]]]:
    """Run the rounds of one language; return its loads and its runs per (load, kind)."""
    burst = args.burst or keeps_up(language, install, base_env, 2.0, args.warmup)
    loads = loads_of(burst)
    runs: dict[tuple[str, str], list[Run]] = {}
    for round_ in range(args.rounds):
        order = KINDS[round_ % 3:] + KINDS[:round_ % 3]
        for load, messages in loads.items():
            for kind in order:
                run = run_pair(pair(language, kind, install, messages, args.warmup), base_env,
                               messages, args.seconds, args.warmup)
                runs.setdefault((load, kind), []).append(run)
                print(f'  {language.title} round {round_ + 1}, {load}, {kind}: '
                      f'{run.received_rate:.0f}/s received, '
                      f'{run.cpu_per_received_us:.0f} us CPU/message', flush=True)
    return loads, runs


def report(language: Language, loads: dict[str, int], runs: dict[tuple[str, str], list[Run]],
           rounds: int) -> str:
    """Return a language's table of medians and its goals, each "met" or "NOT met"."""
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
            for kind, at_most in language.goals.items():
                value = cpu['generated'] / cpu[kind]
                goals.append(f'{language.title}, {load}: generated CPU/message <= {at_most}x '
                             f'of {kind}: {value:.2f}x: {verdict(value, at_most)}')
        elif language.rate_goal is not None:
            value = rate['generated'] / rate['hand-written, default']
            goals.append(f'{language.title}, {load}: generated receives >= '
                         f'{language.rate_goal}x the messages/s of hand-written, default: '
                         f'{value:.2f}x: {"met" if value >= language.rate_goal else "NOT met"}')
    return '\n'.join([
        f'{language.title}: hand-written: {language.source}; medians of {rounds} rounds',
        table(['load', 'listener', 'received/s', 'CPU us/message', 'generated / it',
               'CPU us/message per round'], rows),
        *goals])


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
                        help='messages per 10 ms of the middle load (default: found per '
                             'language, the highest rate the hand-written default listener '
                             'keeps up with)')
    parser.add_argument('--languages', nargs='+', choices=tuple(LANGUAGES),
                        default=list(LANGUAGES),
                        help='which listeners to compare (default: both; C++ only where '
                             'rclcpp exists)')
    parser.add_argument('--workspace', metavar='DIR',
                        help='build the pairs in DIR and keep it (built again, not anew, '
                             'when DIR has them: bench_runtime.py builds the same pairs); '
                             'default: a temporary folder')
    args = parser.parse_args(argv)
    print_machine('P3: listener CPU per message received, generated vs hand-written '
                  '(pinned with taskset)')
    if shutil.which('taskset') is None or len(os.sched_getaffinity(0)) < 2:
        print('skipped: needs taskset and two CPUs')
        return 0
    skip_cpp = cpp_skip_reason() if 'cpp' in args.languages else None
    languages = [LANGUAGES[name] for name in args.languages if name == 'python' or not skip_cpp]
    reports = []
    with pairs_workspace(args.workspace, LANGUAGES['cpp'] in languages,
                         'robmosys-bench-msg-') as install:
        base_env = ros_env.workspace_env(install, ros_env.loopback_env(ros_env.free_domain_id()))
        for language in languages:
            loads, runs = measure(language, install, base_env, args)
            reports.append(report(language, loads, runs, args.rounds))
    print('\n'.join(reports))
    if skip_cpp:
        print(f'C++: skipped: {skip_cpp}')
    print_end()
    return 0


if __name__ == '__main__':
    raise SystemExit(main())
