# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""Benchmark 1: generation time per component stays flat as a workspace grows.

Compares the generation of synthetic workspaces of N = 10, 100 and 1000
components (with their service definitions and systems, see ``synthetic.py``),
in this process, through the library, as ``colcon build`` runs it: load and
validate every model, plan every package, render and write it into a temporary
folder. Prints the time per component at each N and its ratio to the time per
component at the smallest N, which should stay near 1.00x; the same for a second
generation with nothing changed (every file is compared, none is written). Each
first generation is also compared with writing the very files it wrote, by plain
``open()`` and ``write()`` into a fresh folder (a folder made once): what putting
those packages on this disk costs at the least, however they were made. Wall-clock
time is what a user waits; the CPU time of this process leaves out waiting for the
disk (every file written is synced) and for the other processes of a busy machine.

Last, what each colcon process that checks a changed model file pays once for the
schema, each in a fresh interpreter, alternated: compiling it with fastjsonschema,
against reading the compiled schema back from the build tree's cache
(``build/.robmosys-cache``), where a build keeps it.

    make bench-generation                  # or: .venv/bin/python bench/bench_generation.py
    .venv/bin/python bench/bench_generation.py --profile 1000   # where the time goes
    .venv/bin/python bench/bench_generation.py --tmpdir /dev/shm  # without the disk
"""

from __future__ import annotations

import argparse
import cProfile
from dataclasses import dataclass, field
import os
from pathlib import Path
import pstats
import resource
import subprocess
import sys
import tempfile
import time
from typing import Sequence

from benchlib import print_end, print_machine, ratio, spread, table
from colcon_robmosys.check import find_model_files, load_workspace, ModelCache
from colcon_robmosys.check.cache import CACHE_DIR
from colcon_robmosys.check.index import InterfaceIndex
from colcon_robmosys.generators import create_missing_user_files, fingerprint
from colcon_robmosys.generators import generate_package
from colcon_robmosys.generators import plan_package, StampStore, unchanged_package
import generation_cli
from synthetic import ros_index, write_workspace


@dataclass(frozen=True)
class Phases:
    """The seconds each step of one generation of a workspace took."""

    load: float
    plan: float
    write: float
    written: int
    unchanged: int
    #: CPU seconds of this process for the whole generation: unlike the wall-clock
    #: time it leaves out waiting for the disk and for other processes
    cpu: float

    @property
    def total(self) -> float:
        """Return the seconds of the whole generation."""
        return self.load + self.plan + self.write


def generate_workspace(src: Path, out: Path, index: InterfaceIndex) -> Phases:
    """Generate every package of the models below src into out/<package>.

    The steps of ``colcon build`` and ``colcon robmosys-generate``, minus colcon:
    find and load the models, validate them together, plan each package, create
    the user's missing implementation files, render and write the packages.
    """
    start, cpu_start = time.perf_counter(), time.process_time()
    # as colcon build keeps them in build/
    cache = ModelCache(out / CACHE_DIR)
    stamps = StampStore(out / CACHE_DIR / 'stamps')
    result = load_workspace(find_model_files([src]), index, cache)
    result.raise_errors()
    loaded = time.perf_counter()
    workspace = result.workspace
    todo = []
    written = unchanged = 0
    for model in workspace.models:
        inputs = fingerprint(result, model.package, standalone=True)
        report = unchanged_package(out / model.package, stamps, inputs)
        if report is None:
            todo.append((plan_package(workspace, model.package), inputs))
        else:
            unchanged += len(report.unchanged)
    planned = time.perf_counter()
    for plan, inputs in todo:
        create_missing_user_files(plan)
        report = generate_package(plan, out / plan.name, stamps=stamps,
                                  fingerprint=inputs)
        written += len(report.written)
        unchanged += len(report.unchanged)
    done = time.perf_counter()
    return Phases(loaded - start, planned - loaded, done - planned, written, unchanged,
                  time.process_time() - cpu_start)


def write_plainly(out: Path, floor: Path) -> tuple[float, float]:
    """Write the files a generation wrote into out (its cache aside) below floor, plainly.

    :returns: the wall-clock and CPU seconds of the writing alone (the files
      are read beforehand)
    """
    files = {p.relative_to(out): p.read_bytes() for p in sorted(out.rglob('*'))
             if p.is_file() and CACHE_DIR not in p.relative_to(out).parts}
    # the writes of the generations before, and the removals of earlier samples, are
    # flushed first: left pending, they made this floor six times cp -r (issue 28)
    os.sync()
    start, cpu_start = time.perf_counter(), time.process_time()
    made = set()
    for relative, data in files.items():
        folder = floor / relative.parent
        if folder not in made:
            folder.mkdir(parents=True, exist_ok=True)
            made.add(folder)
        with open(floor / relative, 'wb') as stream:
            stream.write(data)
    return time.perf_counter() - start, time.process_time() - cpu_start


def _sum(phases: Sequence[Phases]) -> Phases:
    return Phases(*(sum(getattr(p, f) for p in phases) for f in
                    ('load', 'plan', 'write', 'written', 'unchanged', 'cpu')))


@dataclass
class Samples:
    """The generations measured at one N: each sample covers ``batch`` workspaces."""

    components: int
    batch: int
    packages: int = 0
    first: list[Phases] = field(default_factory=list)
    again: list[Phases] = field(default_factory=list)
    #: (wall, CPU) seconds of writing the files of each first generation plainly
    plain: list[tuple[float, float]] = field(default_factory=list)


#: Every CPP_EVERY-th component of the synthetic workspaces is a C++ one (0: none).
CPP_EVERY = 5


def measure_once(components: int, batch: int,
                 index: InterfaceIndex) -> tuple[int, Phases, Phases, tuple[float, float]]:
    """Generate ``batch`` fresh workspaces of that many components: from nothing, then again.

    :returns: the packages of a workspace, the sums of the phases of the two
      generations of every workspace, and the (wall, CPU) seconds of writing the
      files of the first generations plainly
    """
    with tempfile.TemporaryDirectory(prefix='robmosys-bench-gen-') as tmp:
        roots = [Path(tmp) / str(b) for b in range(batch)]
        for root in roots:
            shape = write_workspace(root / 'src', components, cpp_every=CPP_EVERY)
        os.sync()
        first = _sum([generate_workspace(r / 'src', r / 'out', index) for r in roots])
        os.sync()
        again = _sum([generate_workspace(r / 'src', r / 'out', index) for r in roots])
        plain = [write_plainly(r / 'out', r / 'plain') for r in roots]
    if again.written:
        raise RuntimeError(f'a generation with nothing changed wrote {again.written} files')
    return (shape.packages, first, again,
            (sum(p[0] for p in plain), sum(p[1] for p in plain)))


def run(sizes: Sequence[int], repeat: int) -> list[Samples]:
    """Measure every size, interleaved so that a change of load hits every size alike.

    A sample at a small N generates as many components as one at the largest N
    (several workspaces): a sample of a tenth of a second could fit between the
    bursts of other processes on a busy machine, where one of a minute cannot,
    and the smallest of a few samples would favour the small sizes.
    """
    index = ros_index()
    measure_once(min(sizes), 1, index)  # warm up: imports, template compilation, schema
    samples = {n: Samples(n, max(1, max(sizes) // n)) for n in sizes}
    for _ in range(repeat):
        for entry in samples.values():
            packages, first, again, plain = measure_once(entry.components, entry.batch,
                                                         index)
            entry.packages = packages
            entry.first.append(first)
            entry.again.append(again)
            entry.plain.append(plain)
    return [samples[n] for n in sizes]


def _per_component(phases: list[Phases], components: int) -> Phases:
    """Return the fastest sample, per component, in milliseconds (CPU: the least CPU)."""
    fastest = min(phases, key=lambda p: p.total)
    scale = 1000 / components
    return Phases(fastest.load * scale, fastest.plan * scale, fastest.write * scale,
                  fastest.written, fastest.unchanged,
                  min(p.cpu for p in phases) * scale)


def _table(results: list[Samples], which: str) -> str:
    """Return the figures of one kind of generation, per component, with their ratios."""
    rows = []
    base = base_cpu = 0.0
    for entry in results:
        samples = getattr(entry, which)
        assert samples is not None
        fastest = _per_component(samples, entry.components * entry.batch)
        base = base or fastest.total
        base_cpu = base_cpu or fastest.cpu
        files = (fastest.written if which == 'first' else fastest.unchanged) // entry.batch
        rows.append([
            entry.components, entry.packages, files, f'{len(samples)} x {entry.batch}',
            f'{fastest.load:.2f}', f'{fastest.plan:.3f}', f'{fastest.write:.2f}',
            f'{fastest.total:.2f}', ratio(fastest.total, base),
            f'{fastest.cpu:.2f}', ratio(fastest.cpu, base_cpu),
        ])
        if which == 'first':
            plain = min(p[0] for p in entry.plain) * 1000 / (entry.components * entry.batch)
            rows[-1] += [f'{plain:.2f}', ratio(fastest.total, plain)]
    step = 'render+write' if which == 'first' else 'render+compare'
    header = ['N components', 'packages', 'files', 'samples x workspaces',
              'load+validate ms/comp',
              'plan ms/comp', f'{step} ms/comp', 'total ms/comp', 'ratio to N0',
              'CPU ms/comp', 'CPU ratio to N0']
    if which == 'first':
        header += ['plain writing ms/comp', 'total / plain writing']
    return table(header, rows)


#: The goals of issue 16 (P1), for the largest workspace.
GOAL_FIRST_S = 2.0
GOAL_AGAIN_S = 0.5
GOAL_FLAT = 1.10
GOAL_PEAK_MB = 300


def goals(results: list[Samples]) -> list[str]:
    """Return how the largest workspace fares against the goals, one line each."""
    largest, smallest = results[-1], results[0]

    def best(entry: Samples, which: str) -> Phases:
        return min(getattr(entry, which), key=lambda p: p.total)

    def met(ok: bool) -> str:
        return 'met' if ok else 'NOT met'

    first, again = best(largest, 'first'), best(largest, 'again')
    plain_wall = min(p[0] for p in largest.plain)
    plain_cpu = min(p[1] for p in largest.plain)
    per_large = first.total / (largest.components * largest.batch)
    per_small = best(smallest, 'first').total / (smallest.components * smallest.batch)
    flat = per_large / per_small
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    n = largest.components
    return [
        f'goals at N={n} (first and no-change generation: fastest sample, one workspace):',
        f'  first generation: {first.total:.2f} s wall, {first.cpu:.2f} s CPU '
        f'(goal < {GOAL_FIRST_S} s: wall {met(first.total < GOAL_FIRST_S)}, '
        f'CPU {met(first.cpu < GOAL_FIRST_S)})',
        '    writing the files of its packages plainly (open, write): '
        f'{plain_wall:.2f} s wall, {plain_cpu:.2f} s CPU; the generation takes '
        f'{ratio(first.total, plain_wall)} the wall time, {ratio(first.cpu, plain_cpu)} '
        'the CPU time (fastest of each)',
        f'  no-change generation: {again.total:.2f} s wall, {again.cpu:.2f} s CPU '
        f'(goal < {GOAL_AGAIN_S} s: wall {met(again.total < GOAL_AGAIN_S)}, '
        f'CPU {met(again.cpu < GOAL_AGAIN_S)})',
        f'  time per component at N={n} / at N={smallest.components}: {flat:.3f}x '
        f'(goal: flat, < {GOAL_FLAT:.2f}x: {met(flat < GOAL_FLAT)})',
        f'  peak memory (max RSS of this process, every size): {peak:.0f} MB '
        f'(goal < {GOAL_PEAK_MB} MB: {met(peak < GOAL_PEAK_MB)})',
    ]


def report(results: list[Samples]) -> str:
    """Return the figures and their ratios to the smallest workspace."""
    lines = ['first generation (from nothing; every file written):',
             _table(results, 'first'), '',
             'second generation, nothing changed (every file compared, none written):',
             _table(results, 'again'), '',
             'spread of the first generation samples (s):']
    for entry in results:
        assert entry.first is not None
        lines.append(f'  N={entry.components}: {spread([p.total for p in entry.first])}')
    return '\n'.join(lines + [''] + goals(results))


def profile(components: int, limit: int = 30) -> None:
    """Print where one generation of that size spends its time."""
    index = ros_index()
    measure_once(10, 1, index)  # warm up
    profiler = cProfile.Profile()
    with tempfile.TemporaryDirectory(prefix='robmosys-bench-gen-') as tmp:
        src, out = Path(tmp) / 'src', Path(tmp) / 'out'
        write_workspace(src, components, cpp_every=CPP_EVERY)
        profiler.runcall(generate_workspace, src, out, index)
    stats = pstats.Stats(profiler)
    stats.sort_stats('cumulative').print_stats(limit)
    stats.sort_stats('tottime').print_stats(limit)


#: what a fresh interpreter runs to time the schema: compiled, or read back from a cache
_SCHEMA_CODE = {
    'compiled': 'from colcon_robmosys.model import schema\n'
                'start = time.perf_counter()\n'
                'schema.use_fast_check(schema.compile_fast_check())\n',
    'read back': 'from colcon_robmosys.check import ModelCache\n'
                 'cache = ModelCache(pathlib.Path(sys.argv[1]))\n'
                 'start = time.perf_counter()\n'
                 'cache.use_compiled_schema()\n',
}


def schema_cost(rounds: int) -> str:
    """Time making the compiled schema in fresh interpreters; return the lines to print."""
    times: dict[str, list[float]] = {way: [] for way in _SCHEMA_CODE}

    def timed(way: str, folder: str) -> float:
        code = 'import pathlib, sys, time\n' + _SCHEMA_CODE[way] + \
            'print(time.perf_counter() - start)\n'
        done = subprocess.run([sys.executable, '-c', code, folder], check=True,
                              capture_output=True, text=True, timeout=120)
        return float(done.stdout)

    with tempfile.TemporaryDirectory(prefix='robmosys-bench-schema-') as folder:
        timed('read back', folder)  # finds none: compiles and keeps it, as a build does
        for round_ in range(rounds):
            for way in list(_SCHEMA_CODE)[::1 if round_ % 2 == 0 else -1]:
                times[way].append(timed(way, folder))
    compiled, read_back = min(times['compiled']), min(times['read back'])
    return '\n'.join([
        f'the schema, once per colcon process that checks a changed model file '
        f'(fastest of {rounds}, a fresh interpreter each):',
        f'  compiled: {compiled * 1e3:.1f} ms; read back from the build tree: '
        f'{read_back * 1e3:.1f} ms ({ratio(read_back, compiled)} of compiling it)',
        f'  compiled: {spread(times["compiled"])}',
        f'  read back: {spread(times["read back"])}'])


def main(argv: Sequence[str] | None = None) -> int:
    """Run the benchmark and print its figures."""
    parser = argparse.ArgumentParser(description=__doc__.split('\n\n')[0])
    parser.add_argument('--sizes', type=int, nargs='+', default=[10, 100, 1000],
                        help='numbers of components (default: 10 100 1000)')
    parser.add_argument('--repeat', type=int, default=3,
                        help='samples per size; the fastest counts (default: 3)')
    parser.add_argument('--profile', type=int, metavar='N',
                        help='profile one generation of N components instead')
    parser.add_argument('--cpp-every', type=int, default=CPP_EVERY,
                        help='make every Nth component a C++ one, 0 for none '
                        f'(default: {CPP_EVERY})')
    parser.add_argument('--schema-rounds', type=int, default=5,
                        help='fresh interpreters timing the schema each way (default: 5)')
    parser.add_argument('--cli-size', type=int, default=1000, metavar='N',
                        help='components of the workspace that the CLI generates '
                        '(issue 28, P1), 0 to skip (default: 1000)')
    parser.add_argument('--cli-rounds', type=int, default=2,
                        help='rounds of the CLI steps; the fastest counts (default: 2)')
    parser.add_argument('--tmpdir', type=Path,
                        help='where to write the workspaces (default: the system temp folder)')
    args = parser.parse_args(argv)
    globals()['CPP_EVERY'] = args.cpp_every
    if args.tmpdir:
        tempfile.tempdir = str(args.tmpdir)
    if args.profile:
        profile(args.profile)
        return 0
    print_machine('generation scaling: time per component at N components vs at '
                  f'N0={min(args.sizes)}, written below {tempfile.gettempdir()}')
    if args.cli_size:
        # first: the in-process steps remove what they wrote, which slows the
        # files created after (generation_cli.measure)
        times = generation_cli.measure(args.cli_size, args.cli_rounds, CPP_EVERY)
        print('\n'.join(generation_cli.report(args.cli_size, times)))
    results = run(sorted(args.sizes), args.repeat)
    print(report(results))
    print(schema_cost(args.schema_rounds))
    print_end()
    return 0


if __name__ == '__main__':
    raise SystemExit(main())
