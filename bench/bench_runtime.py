# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""Benchmark 3: message rate and latency of generated nodes vs hand-written rclpy ones.

Compares a generated Python publisher/subscriber pair (two component models,
built with colcon in a temporary workspace) with the hand-written rclpy lifecycle
pair of ``handwritten_pubsub.py``: same message type (std_msgs/msg/Header, the
stamp carries the send time), QoS (keep_last 10, reliable, volatile), timer period
(10 ms), callback groups and executor (the generated pair's default, rclpy's
EventsExecutor: neither makes a blocking call), and the same code in the timer and
the subscription. Both pairs run as real processes on loopback DDS,
each in a ROS domain of its own, configured and activated through their lifecycle
services, in alternation. Two loads:

- latency: one message per period (100 Hz); latency = receive time - stamp;
- throughput: ``--burst`` messages per period; rates of sending and of receiving.

Under both, the CPU time each process uses per message: on a busy machine rates and
latencies follow the load of other processes, CPU time per message much less.

The same comparison in C++ where rclcpp, rclcpp_lifecycle and rclcpp_components
exist (a ROS 2 install on AMENT_PREFIX_PATH or CMAKE_PREFIX_PATH): the same two
models with ``language: cpp``, their user code in ``generated_cpp/``, against the
hand-written rclcpp_lifecycle pair of the ament_cmake package ``handwritten_cpp/``,
all built by the same colcon build. Without rclcpp the C++ pairs are skipped and
the reason is printed.

Prints generated / hand-written ratios for each figure, per language.

    make bench-runtime                     # or: .venv/bin/python bench/bench_runtime.py
"""

from __future__ import annotations

import argparse
import contextlib
from dataclasses import dataclass
import json
from pathlib import Path
import shutil
import statistics
import sys
import tempfile
import time
from typing import Any, Iterator, Mapping, Sequence

import yaml

from benchlib import print_end, print_machine, ratio, REPO, table
from colcon_robmosys.devtools import ros_env
from colcon_robmosys.devtools.system import LifecycleDriver, wait_until
from colcon_robmosys.package_selection.robmosys import missing_prefix_packages

HANDWRITTEN = REPO / 'bench' / 'handwritten_pubsub.py'
#: the executor of the hand-written Python pair: the one the generated pair gets by default
HANDWRITTEN_EXECUTOR = 'events'
#: the ament_cmake package of the hand-written C++ pair
HANDWRITTEN_CPP = REPO / 'bench' / 'handwritten_cpp'
#: the user code (implementation files) of the generated C++ pair
GENERATED_CPP = REPO / 'bench' / 'generated_cpp'
#: what the C++ pairs need from a ROS 2 install
CPP_PACKAGES = ('rclcpp', 'rclcpp_lifecycle', 'rclcpp_components')
TOPIC = '/bench_samples'
QOS = {'depth': 10, 'reliability': 'reliable', 'durability': 'volatile'}
METADATA = {'license': 'Apache-2.0',
            'maintainers': [{'name': 'Benchmark Team', 'email': 'bench@example.com'}]}

# The code of handwritten_pubsub.py's timer and subscription, as model functions.
TALKER = {
    'name': 'Talker', 'package': 'bench_talker', 'language': 'python',
    'ports': {'pSample': {'pattern': 'push', 'role': 'provided',
                          'type': 'std_msgs/msg/Header', 'qos': QOS}},
    'activities': {'Publish': {'period': 0.01, 'functions': ['fPublish']}},
    'functions': {
        'fSetUp': {'code': 'import time\n'
                           'self.now_ns = time.time_ns\n'
                           'self.burst = self.params.burst\n'
                           "self.frame = 'x' * self.params.payload\n"
                           'self.sent = 0\n'
                           'self.first = self.last = 0\n'},
        'fPublish': {'code': 'for _ in range(self.burst):\n'
                             '    now = self.now_ns()\n'
                             '    message = Header(frame_id=self.frame)\n'
                             '    message.stamp.sec, message.stamp.nanosec = '
                             'divmod(now, 1_000_000_000)\n'
                             '    self.pSample.publish(message)\n'
                             'self.sent += self.burst\n'
                             'self.first = self.first or now\n'
                             'self.last = now\n'},
        'fReport': {'code': 'import json\n'
                            "print('BENCH talker ' + json.dumps({'sent': self.sent, "
                            "'first': self.first, 'last': self.last}), flush=True)\n"},
    },
    'lifecycle': {'on_configure': ['fSetUp'], 'on_deactivate': ['fReport']},
    'parameters': {'burst': {'type': 'int', 'default': 1},
                   'payload': {'type': 'int', 'default': 0}},
}
LISTENER = {
    'name': 'Listener', 'package': 'bench_listener', 'language': 'python',
    # the cheapest executor (Python's default is multi-threaded: docs/model-format.md)
    'executor': 'events',
    'ports': {'rSample': {'pattern': 'push', 'role': 'required',
                          'type': 'std_msgs/msg/Header', 'qos': QOS}},
    'activities': {'Receive': {'trigger': 'rSample', 'functions': ['fReceive']}},
    'functions': {
        'fSetUp': {'code': 'import time\n'
                           'self.now_ns = time.time_ns\n'
                           'self.warmup_ns = int(self.params.warmup * 1e9)\n'
                           'self.latencies = []\n'
                           'self.first = self.start = self.last = 0\n'},
        'fReceive': {'code': 'now = self.now_ns()\n'
                             'if not self.first:\n'
                             '    self.first = now\n'
                             "    print('BENCH listener first', flush=True)\n"
                             'if now - self.first < self.warmup_ns:\n'
                             '    return\n'
                             'self.start = self.start or now\n'
                             'self.latencies.append(now - commobj.stamp.sec * 1_000_000_000 '
                             '- commobj.stamp.nanosec)\n'
                             'self.last = now\n'},
        'fReport': {'code': 'import json\n'
                            "print('BENCH listener ' + json.dumps({'start': self.start, "
                            "'last': self.last, 'latencies': self.latencies}), flush=True)\n"},
    },
    'lifecycle': {'on_configure': ['fSetUp'], 'on_deactivate': ['fReport']},
    'parameters': {'warmup': {'type': 'double', 'default': 0.5}},
}


def cpp_model(model: dict[str, Any]) -> dict[str, Any]:
    """Return the C++ twin of a Python model: its functions are in GENERATED_CPP."""
    functions = {
        name: {'description': f'In bench/generated_cpp/{model["name"]}_impl.cpp.'}
        for name in model['functions']}
    return {**model, 'package': f'{model["package"]}_cpp', 'language': 'cpp',
            'functions': functions}


TALKER_CPP = cpp_model(TALKER)
LISTENER_CPP = cpp_model(LISTENER)

#: language -> the kinds of pair compared: generated first, then hand-written
PAIRS = {'python': ('generated', 'hand-written'),
         'cpp': ('generated C++', 'hand-written C++')}


@dataclass(frozen=True)
class Run:
    """What one run of a pair measured."""

    sent_rate: float
    received_rate: float
    received: int
    latency_us: dict[str, float]
    #: CPU time (user + system) of the talker per message sent and of the listener
    #: per message received, over the measured seconds: unlike rates and latencies,
    #: it hardly depends on what else the machine runs
    cpu_per_sent_us: float
    cpu_per_received_us: float


def write_models(src: Path, cpp: bool = False) -> None:
    """Write the packages of the pairs into a workspace's src folder.

    Always the models of the generated Python pair; with ``cpp``, also the models of the
    generated C++ pair with their implementation files, and the hand-written C++ package.
    """
    for model in (TALKER, LISTENER) + ((TALKER_CPP, LISTENER_CPP) if cpp else ()):
        package = str(model['package'])
        path = src / package / 'robmosys.yaml'
        path.parent.mkdir(parents=True)
        path.write_text(yaml.safe_dump(
            {'robmosys': 1, 'defaults': METADATA, 'components': [model]}, sort_keys=False),
            encoding='utf-8')
        if model['language'] == 'cpp':
            code = src / package / 'src' / package
            code.mkdir(parents=True)
            for suffix in ('hpp', 'cpp'):
                name = f'{model["name"]}_impl.{suffix}'
                shutil.copyfile(GENERATED_CPP / name, code / name)
    if cpp:
        shutil.copytree(HANDWRITTEN_CPP, src / 'bench_handwritten_cpp')


@contextlib.contextmanager
def pairs_workspace(workspace: str | None, cpp: bool, prefix: str) -> Iterator[Path]:
    """Yield the install folder of a built workspace of the pairs.

    Without ``workspace``, written and built in a temporary folder, removed after. With
    it, written there the first time and built (again: colcon builds what changed), and
    kept: benchmarks of the same pairs (this one, bench_messages.py) share one build.
    """
    if workspace is None:
        with tempfile.TemporaryDirectory(prefix=prefix) as tmp:
            write_models(Path(tmp) / 'src', cpp=cpp)
            yield build(Path(tmp))
        return
    root = Path(workspace)
    if not (root / 'src').exists():
        write_models(root / 'src', cpp=cpp)
    elif (root / 'src' / str(TALKER_CPP['package'])).exists() != cpp:
        raise SystemExit(f'{root}: its pairs were written {"without" if cpp else "with"} '
                         'C++: remove it, or give another --workspace')
    yield build(root)


def build(root: Path) -> Path:
    """Build the workspace with colcon, optimised as a robot runs it; return the install folder.

    Both sides of a comparison are built alike. Unoptimised, the C++ of the generated
    node (the runtime's templates and wrappers, which the compiler inlines in a Release
    build) cost it 1.2x of the hand-written one at 100 Hz; optimised, about 1.03x.
    """
    env = ros_env.loopback_env(ros_env.free_domain_id())
    result = ros_env.run([str(Path(sys.prefix) / 'bin' / 'colcon'), 'build',
                          '--cmake-args', '-DCMAKE_BUILD_TYPE=Release'],
                         env=env, cwd=root, timeout=900)
    if result.returncode:
        raise RuntimeError(f'colcon build failed:\n{result.stdout}{result.stderr}')
    return root / 'install'


def commands(kind: str, install: Path, burst: int, warmup: float) -> dict[str, list[str]]:
    """Return the command lines of the talker and the listener of one kind of pair."""
    if kind in ('generated', 'generated C++'):
        suffix = '' if kind == 'generated' else '_cpp'
        talker = [str(install / f'bench_talker{suffix}' / 'lib' / f'bench_talker{suffix}' /
                      'Talker')]
        listener = [str(install / f'bench_listener{suffix}' / 'lib' /
                        f'bench_listener{suffix}' / 'Listener')]
    elif kind == 'hand-written C++':
        pubsub = str(install / 'bench_handwritten_cpp' / 'lib' / 'bench_handwritten_cpp' /
                     'pubsub')
        talker, listener = [pubsub, 'talker', 'multi-threaded'], [pubsub, 'listener',
                                                                  'multi-threaded']
    else:
        talker = [sys.executable, str(HANDWRITTEN), 'talker', HANDWRITTEN_EXECUTOR]
        listener = [sys.executable, str(HANDWRITTEN), 'listener', HANDWRITTEN_EXECUTOR]
    return {
        'talker': talker + ['--ros-args', '-r', '__node:=talker', '-p', f'burst:={burst}',
                            '-r', f'pSample:={TOPIC}'],
        'listener': listener + ['--ros-args', '-r', '__node:=listener',
                                '-p', f'warmup:={warmup}', '-r', f'rSample:={TOPIC}'],
    }


def _report(output: str, role: str) -> dict[str, Any] | None:
    marker = f'BENCH {role} {{'
    for line in output.splitlines():
        if line.startswith(marker):
            return json.loads(line[len(marker) - 1:])
    return None


def group_cpu_seconds(pgid: int) -> float:
    """Return the CPU seconds the live threads of a process group have run, to the ns.

    Each thread's time on a CPU is the first field of ``/proc/<pid>/task/<tid>/schedstat``,
    in nanoseconds; ``/proc/<pid>/stat`` counts in clock ticks of 10 ms, a tenth of what a
    C++ listener at 100 Hz spends in a second. A difference of two readings counts the
    threads that live through both: the listeners' executors keep their threads.
    """
    nanoseconds = 0
    for stat in Path('/proc').glob('[0-9]*/stat'):
        try:
            text = stat.read_text()
        except OSError:
            continue  # gone meanwhile
        # after the command name in parentheses: state, ppid, pgrp, ...
        fields = text[text.rindex(')') + 2:].split()
        if int(fields[2]) != pgid:
            continue
        for task in (stat.parent / 'task').glob('[0-9]*'):
            try:
                nanoseconds += int((task / 'schedstat').read_text().split()[0])
            except (OSError, IndexError, ValueError):
                continue  # a thread that ended meanwhile
    return nanoseconds / 1e9


def run_pair(cmds: dict[str, list[str]], base_env: dict[str, str], burst: int,
             seconds: float, warmup: float) -> Run:
    """Run one pair: configure, activate, let it work, deactivate, read its reports."""
    domain_id = ros_env.free_domain_id()
    env = ros_env.loopback_env(domain_id, base_env)
    with contextlib.ExitStack() as stack:
        processes = {role: stack.enter_context(ros_env.background(cmd, env=env))
                     for role, cmd in cmds.items()}
        driver = stack.enter_context(LifecycleDriver(domain_id))

        def transition(role: str, label: str) -> None:
            if not driver.transition(f'/{role}', label):
                raise RuntimeError(f'{role} failed to {label}:\n{processes[role].output()}')

        for role in ('listener', 'talker'):
            transition(role, 'configure')
        # the window starts once the two have found each other, not at a fixed time: on
        # a loaded machine discovery took longer than the warm-up, and the listener's
        # first message (which starts its warm-up) came after the talker stopped
        if not wait_until(lambda: driver.node.count_publishers(TOPIC) >= 1 and
                          driver.node.count_subscribers(TOPIC) >= 1, timeout=60):
            raise RuntimeError(f'the talker and the listener did not meet on {TOPIC}')
        for role in ('listener', 'talker'):
            transition(role, 'activate')
        # and the window starts once messages flow: the graph shows both ends before DDS
        # has matched them (up to seconds later on a loaded machine)
        if not wait_until(lambda: 'BENCH listener first' in processes['listener'].output(),
                          timeout=60):
            raise RuntimeError('the listener received nothing:\n' +
                               processes['listener'].output()[-3000:])
        time.sleep(warmup)
        # each process leads a process group of its own (ros_env.background)
        cpu_start = {role: group_cpu_seconds(p.proc.pid) for role, p in processes.items()}
        start = time.perf_counter()
        time.sleep(seconds)
        cpu = {role: group_cpu_seconds(p.proc.pid) - cpu_start[role]
               for role, p in processes.items()}
        measured = time.perf_counter() - start
        transition('talker', 'deactivate')
        time.sleep(0.3)  # messages in flight
        transition('listener', 'deactivate')
        reports: dict[str, Any] = {}

        def reported() -> bool:
            for role, process in processes.items():
                reports[role] = _report(process.output(), role)
            return all(reports.values())

        if not wait_until(reported, timeout=10):
            raise RuntimeError('no report:\n' + '\n'.join(
                f'--- {role}:\n{p.output()[-3000:]}' for role, p in processes.items()))
    talker, listener = reports['talker'], reports['listener']
    latencies = sorted(listener['latencies'])
    if len(latencies) < 2:
        raise RuntimeError(f'the listener received {len(latencies)} messages')
    sent_span = (talker['last'] - talker['first']) / 1e9
    received_span = (listener['last'] - listener['start']) / 1e9
    quantiles = statistics.quantiles(latencies, n=100, method='inclusive')
    sent_rate = (talker['sent'] - burst) / sent_span if sent_span > 0 else 0.0
    received_rate = (len(latencies) - 1) / received_span if received_span > 0 else 0.0
    return Run(
        sent_rate=sent_rate, received_rate=received_rate, received=len(latencies),
        latency_us={'p50': quantiles[49] / 1e3, 'p90': quantiles[89] / 1e3,
                    'p99': quantiles[98] / 1e3, 'max': latencies[-1] / 1e3},
        cpu_per_sent_us=1e6 * cpu['talker'] / max(sent_rate * measured, 1),
        cpu_per_received_us=1e6 * cpu['listener'] / max(received_rate * measured, 1))


def cpp_skip_reason(environ: Mapping[str, str] | None = None) -> str | None:
    """Say why the C++ pairs cannot be built here, or None when they can.

    They can where a prefix (this environment's, or one on AMENT_PREFIX_PATH or
    CMAKE_PREFIX_PATH) provides rclcpp, rclcpp_lifecycle and rclcpp_components, which
    is what colcon-robmosys's build task looks for before it builds a C++ component.
    """
    missing = missing_prefix_packages(CPP_PACKAGES, [sys.prefix], environ)
    if not missing:
        return None
    return (f'{", ".join(missing)} not found in {sys.prefix} nor on AMENT_PREFIX_PATH or '
            'CMAKE_PREFIX_PATH (not on PyPI); run this with a ROS 2 install sourced')


METRICS = (  # mode, label, key, higher is better
    ('latency', 'latency p50 (us)', 'p50', False),
    ('latency', 'latency p90 (us)', 'p90', False),
    ('latency', 'latency p99 (us)', 'p99', False),
    ('latency', 'talker CPU us/message sent', 'cpu_per_sent_us', False),
    ('latency', 'listener CPU us/message received', 'cpu_per_received_us', False),
    ('throughput', 'messages sent/s', 'sent_rate', True),
    ('throughput', 'messages received/s', 'received_rate', True),
    ('throughput', 'talker CPU us/message sent', 'cpu_per_sent_us', False),
    ('throughput', 'listener CPU us/message received', 'cpu_per_received_us', False),
)


def _value(run: Run, key: str) -> float:
    return run.latency_us[key] if key in run.latency_us else float(getattr(run, key))


def report(runs: dict[tuple[str, str], list[Run]], burst: int,
           kinds: tuple[str, str] = PAIRS['python']) -> str:
    """Return each figure's best value over the rounds, per pair, and their ratio.

    ``kinds`` names the generated pair and the hand-written one in ``runs``.
    """
    rows = []
    for mode, label, key, higher in METRICS:
        if (mode, kinds[0]) not in runs:
            continue
        values = {kind: [_value(r, key) for r in runs[(mode, kind)]] for kind in kinds}
        pick = max if higher else min
        generated, handwritten = pick(values[kinds[0]]), pick(values[kinds[1]])
        rows.append([
            f'{mode} ({"1" if mode == "latency" else burst}/10 ms)', label,
            f'{generated:.0f}', f'{handwritten:.0f}', ratio(generated, handwritten),
            ' '.join(f'{v:.0f}' for v in values[kinds[0]]),
            ' '.join(f'{v:.0f}' for v in values[kinds[1]]),
        ])
    return table(['load', 'figure', 'generated', 'hand-written', 'ratio gen/hand',
                  'generated per round', 'hand-written per round'], rows)


def main(argv: Sequence[str] | None = None) -> int:
    """Run the benchmark and print its figures."""
    parser = argparse.ArgumentParser(description=__doc__.split('\n\n')[0])
    parser.add_argument('--seconds', type=float, default=5.0,
                        help='measured seconds per run, after the warm-up (default: 5)')
    parser.add_argument('--warmup', type=float, default=1.0,
                        help='seconds of each run not measured (default: 1)')
    parser.add_argument('--burst', type=int, default=100,
                        help='messages per 10 ms period under throughput load (default: 100)')
    parser.add_argument('--rounds', type=int, default=3,
                        help='runs per pair and load; the best counts (default: 3)')
    parser.add_argument('--loads', nargs='+', choices=('latency', 'throughput'),
                        default=['latency', 'throughput'],
                        help='which loads to run (default: both)')
    parser.add_argument('--languages', nargs='+', choices=tuple(PAIRS),
                        default=list(PAIRS),
                        help='which pairs to compare (default: both; C++ only where '
                             'rclcpp exists)')
    parser.add_argument('--workspace', metavar='DIR',
                        help='build the pairs in DIR and keep it (built again, not anew, '
                             'when DIR has them: bench_messages.py builds the same pairs); '
                             'default: a temporary folder')
    args = parser.parse_args(argv)
    print_machine('run time: generated pub/sub pairs vs hand-written ones (Python; C++ '
                  'where rclcpp exists)')
    skip_cpp = cpp_skip_reason() if 'cpp' in args.languages else 'not asked for'
    languages = [lang for lang in args.languages if lang == 'python' or not skip_cpp]
    with pairs_workspace(args.workspace, 'cpp' in languages, 'robmosys-bench-run-') as install:
        base_env = ros_env.workspace_env(install, ros_env.loopback_env(ros_env.free_domain_id()))
        runs: dict[tuple[str, str], list[Run]] = {}
        for round_ in range(args.rounds):
            for language in languages:
                # alternate which pair goes first, so that a drift of the load hits both
                kinds = PAIRS[language][::1 if round_ % 2 == 0 else -1]
                for mode in args.loads:
                    burst = 1 if mode == 'latency' else args.burst
                    for kind in kinds:
                        cmds = commands(kind, install, burst, args.warmup)
                        run = run_pair(cmds, base_env, burst, args.seconds, args.warmup)
                        runs.setdefault((mode, kind), []).append(run)
                        print(f'  round {round_ + 1}, {mode}, {kind}: {run.received} '
                              f'received, p50 {run.latency_us["p50"]:.0f} us, '
                              f'{run.received_rate:.0f}/s received, listener CPU '
                              f'{run.cpu_per_received_us:.0f} us/message', flush=True)
    for language in languages:
        print(f'{"Python" if language == "python" else "C++"}: generated / hand-written')
        print(report(runs, args.burst, PAIRS[language]))
    if 'cpp' not in languages:
        print(f'C++: skipped: {skip_cpp}')
    print_end()
    return 0


if __name__ == '__main__':
    raise SystemExit(main())
