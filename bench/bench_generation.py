# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""Benchmark 1: generation time per component stays flat as a workspace grows.

Compares the generation of synthetic workspaces of N = 10, 100 and 1000
components (with their service definitions and systems, see ``synthetic.py``),
in this process, through the library, as ``colcon build`` runs it: load and
validate every model, plan every package, render and write it into a temporary
folder. Prints the time per component at each N and its ratio to the time per
component at the smallest N, which should stay near 1.00x; the same for a second
generation with nothing changed (every file is compared, none is written).

    make bench-generation                  # or: .venv/bin/python bench/bench_generation.py
    .venv/bin/python bench/bench_generation.py --profile 1000   # where the time goes
"""

from __future__ import annotations

import argparse
import cProfile
from dataclasses import dataclass
from pathlib import Path
import pstats
import tempfile
import time
from typing import Sequence

from benchlib import print_end, print_machine, ratio, spread, table
from colcon_robmosys.generate import create_missing_user_files, generate_package
from colcon_robmosys.model import find_model_files, load_workspace
from colcon_robmosys.model.index import InterfaceIndex
from colcon_robmosys.ros2 import plan_package
from synthetic import ros_index, write_workspace


@dataclass(frozen=True)
class Phases:
    """The seconds each step of one generation of a workspace took."""

    load: float
    plan: float
    write: float
    written: int
    unchanged: int

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
    start = time.perf_counter()
    result = load_workspace(find_model_files([src]), index)
    result.raise_errors()
    loaded = time.perf_counter()
    workspace = result.workspace
    plans = [plan_package(workspace, model.package) for model in workspace.models]
    planned = time.perf_counter()
    written = unchanged = 0
    for plan in plans:
        create_missing_user_files(plan)
        report = generate_package(plan, out / plan.name)
        written += len(report.written)
        unchanged += len(report.unchanged)
    done = time.perf_counter()
    return Phases(loaded - start, planned - loaded, done - planned, written, unchanged)


@dataclass
class Samples:
    """The generations measured at one N."""

    components: int
    packages: int = 0
    first: list[Phases] | None = None
    again: list[Phases] | None = None


def measure_once(components: int, index: InterfaceIndex) -> tuple[int, Phases, Phases]:
    """Generate a fresh workspace of that many components twice: from nothing, then again."""
    with tempfile.TemporaryDirectory(prefix='robmosys-bench-gen-') as tmp:
        src, out = Path(tmp) / 'src', Path(tmp) / 'out'
        shape = write_workspace(src, components)
        first = generate_workspace(src, out, index)
        again = generate_workspace(src, out, index)
    if again.written:
        raise RuntimeError(f'a generation with nothing changed wrote {again.written} files')
    return shape.packages, first, again


def repeats(components: int, repeat: int | None) -> int:
    """Return how often to measure at a size: by default more often where a run is short."""
    if repeat is not None:
        return repeat
    return max(3, min(20, 300 // components))


def run(sizes: Sequence[int], repeat: int | None) -> list[Samples]:
    """Measure every size, interleaved so that a change of load hits every size alike."""
    index = ros_index()
    measure_once(min(sizes), index)  # warm up: imports, template compilation, schema
    samples = {n: Samples(n, first=[], again=[]) for n in sizes}
    for round_ in range(max(repeats(n, repeat) for n in sizes)):
        for n in sizes:
            if round_ < repeats(n, repeat):
                packages, first, again = measure_once(n, index)
                entry = samples[n]
                entry.packages = packages
                assert entry.first is not None and entry.again is not None
                entry.first.append(first)
                entry.again.append(again)
    return [samples[n] for n in sizes]


def _per_component(phases: list[Phases], components: int) -> Phases:
    """Return the fastest generation of the samples, per component, in milliseconds."""
    fastest = min(phases, key=lambda p: p.total)
    scale = 1000 / components
    return Phases(fastest.load * scale, fastest.plan * scale, fastest.write * scale,
                  fastest.written, fastest.unchanged)


def _table(results: list[Samples], which: str) -> str:
    """Return the figures of one kind of generation, per component, with their ratios."""
    rows = []
    base = 0.0
    for entry in results:
        samples = getattr(entry, which)
        assert samples is not None
        fastest = _per_component(samples, entry.components)
        base = base or fastest.total
        files = fastest.written if which == 'first' else fastest.unchanged
        rows.append([
            entry.components, entry.packages, files, len(samples),
            f'{fastest.load:.2f}', f'{fastest.plan:.3f}', f'{fastest.write:.2f}',
            f'{fastest.total:.2f}', ratio(fastest.total, base),
        ])
    step = 'render+write' if which == 'first' else 'render+compare'
    header = ['N components', 'packages', 'files', 'runs', 'load+validate ms/comp',
              'plan ms/comp', f'{step} ms/comp', 'total ms/comp', 'ratio to N0']
    return table(header, rows)


def report(results: list[Samples]) -> str:
    """Return the figures and their ratios to the smallest workspace."""
    lines = ['first generation (from nothing; every file written):',
             _table(results, 'first'), '',
             'second generation, nothing changed (every file compared, none written):',
             _table(results, 'again'), '',
             'spread of whole first generations (s):']
    for entry in results:
        assert entry.first is not None
        lines.append(f'  N={entry.components}: {spread([p.total for p in entry.first])}')
    return '\n'.join(lines)


def profile(components: int, limit: int = 30) -> None:
    """Print where one generation of that size spends its time."""
    index = ros_index()
    measure_once(10, index)
    profiler = cProfile.Profile()
    with tempfile.TemporaryDirectory(prefix='robmosys-bench-gen-') as tmp:
        src, out = Path(tmp) / 'src', Path(tmp) / 'out'
        write_workspace(src, components)
        profiler.runcall(generate_workspace, src, out, index)
    stats = pstats.Stats(profiler)
    stats.sort_stats('cumulative').print_stats(limit)
    stats.sort_stats('tottime').print_stats(limit)


def main(argv: Sequence[str] | None = None) -> int:
    """Run the benchmark and print its figures."""
    parser = argparse.ArgumentParser(description=__doc__.split('\n\n')[0])
    parser.add_argument('--sizes', type=int, nargs='+', default=[10, 100, 1000],
                        help='numbers of components (default: 10 100 1000)')
    parser.add_argument('--repeat', type=int,
                        help='measurements per size; the fastest counts (default: 3, and up '
                        'to 20 for sizes under 100)')
    parser.add_argument('--profile', type=int, metavar='N',
                        help='profile one generation of N components instead')
    args = parser.parse_args(argv)
    if args.profile:
        profile(args.profile)
        return 0
    print_machine('generation scaling: time per component at N components vs at '
                  f'N0={min(args.sizes)}')
    results = run(sorted(args.sizes), args.repeat)
    print(report(results))
    print_end()
    return 0


if __name__ == '__main__':
    raise SystemExit(main())
