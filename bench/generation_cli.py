# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""The generation through the CLI (issue 28, P1), against colcon list and the disk.

In one workspace of N synthetic components, each round times, after a flush of the
disk (``sync``) so that no step pays for the writes of the one before:

- ``colcon list``: what colcon costs before any generation starts;
- a first ``colcon robmosys-generate --output-dir gen``: nothing checked, cached or
  generated before, the implementation files created too;
- the same again, with nothing changed;
- ``cp -r gen``: copying its output, the files and folders it wrote, on the same disk;
- ``cp -r gen`` then ``sync``: the same copy made durable, as the generation makes the
  output a user keeps (it survives a power cut: docs/usage.md); ``cp -r`` alone leaves
  its writes in the kernel's cache;
- writing the same files with Python's ``open()`` and ``write()``, folders made once:
  the floor the in-process benchmark compares with;
- the floor of a first generation's writing: every file it wrote (its packages, the
  implementation files it created beside the models, its check cache and stamps in
  ``build/``) written with ``open()`` and ``write()``, then synced.

The goals: a no-change generation within 1.5x of ``colcon list``; a first generation
within 1.5x of (the no-change generation + ``cp -r`` of its output). Rounds use fresh
workspaces, and nothing is removed until the last round ends (see :func:`measure`).
Each ratio is taken within its round, where the generation and the copy meet the same
disk, and the goals are decided by the median of the rounds' ratios; the fastest of
each step is printed beside it.
"""

from __future__ import annotations

from dataclasses import dataclass, field
import os
from pathlib import Path
import statistics
import subprocess
import sys
import tempfile
import time

from benchlib import ratio, spread
from colcon_robmosys.devtools import ros_env
from synthetic import write_workspace

#: The goals of issue 28, P1.
GOAL_NO_CHANGE = 1.5
GOAL_FIRST = 1.5


@dataclass
class CliTimes:
    """Seconds of each step, one entry per round."""

    listing: list[float] = field(default_factory=list)
    first: list[float] = field(default_factory=list)
    again: list[float] = field(default_factory=list)
    copy: list[float] = field(default_factory=list)
    durable_copy: list[float] = field(default_factory=list)
    plain: list[float] = field(default_factory=list)
    #: every file the first generation wrote, written plainly, then synced
    everything: list[float] = field(default_factory=list)
    #: how many files the first generation wrote, all told
    written: int = 0
    files: int = 0


def _timed_run(command: list[str], cwd: Path, timeout: float) -> float:
    """Run a command after a flush of the disk; return its wall-clock seconds."""
    os.sync()
    env = ros_env.loopback_env(ros_env.free_domain_id())
    start = time.perf_counter()
    result = subprocess.run(command, cwd=cwd, env=env, capture_output=True, text=True,
                            timeout=timeout)
    elapsed = time.perf_counter() - start
    if result.returncode:
        raise RuntimeError(f'{" ".join(command)} failed:\n{result.stdout}{result.stderr}')
    return elapsed


def write_plainly(source: Path, target: Path) -> float:
    """Write the files below source below target with open() and write(); return seconds.

    The files are read beforehand, the disk flushed, the folders made once.
    """
    return write_files({p.relative_to(source): p.read_bytes()
                        for p in sorted(source.rglob('*')) if p.is_file()}, target)


def _files_below(root: Path, *folders: str) -> set[Path]:
    """Return the files below the folders of root, relative to root."""
    return {p.relative_to(root) for folder in folders for p in (root / folder).rglob('*')
            if p.is_file()}


def write_files(files: dict[Path, bytes], target: Path, *, sync: bool = False) -> float:
    """Write files (relative path -> content) below target; return seconds.

    :param sync: flush the disk before the clock stops, as the generation makes its
      writes durable
    """
    os.sync()
    start = time.perf_counter()
    made = set()
    for relative, data in files.items():
        folder = target / relative.parent
        if folder not in made:
            folder.mkdir(parents=True, exist_ok=True)
            made.add(folder)
        with open(target / relative, 'wb') as stream:
            stream.write(data)
    if sync:
        os.sync()
    return time.perf_counter() - start


def measure(components: int, rounds: int, cpp_every: int, timeout: float = 1800) -> CliTimes:
    """Time the steps in ``rounds`` fresh workspaces of that many components.

    Nothing is removed before the last round ends: on ext4 without a journal
    (this project's CI machines), every file created within a minute of many
    removals pays a scan past the inodes freed (the kernel's ``recently_deleted``,
    seen with ``perf``), which made a round's first step up to ten times slower
    than the same step a minute later.
    """
    colcon = str(Path(sys.prefix) / 'bin' / 'colcon')
    times = CliTimes()
    with tempfile.TemporaryDirectory(prefix='robmosys-bench-cli-') as tmp:
        for number in range(rounds):
            root = Path(tmp) / f'round{number}'
            write_workspace(root / 'src', components, cpp_every=cpp_every)
            generate = [colcon, 'robmosys-generate', '--output-dir', 'gen']
            times.listing.append(_timed_run([colcon, 'list'], root, timeout))
            models = _files_below(root, 'src')
            times.first.append(_timed_run(generate, root, timeout))
            # every file the first generation left: the packages, the implementation
            # files it created beside the models, its check cache and stamps
            written = (_files_below(root, 'src') - models) | \
                _files_below(root, 'gen', 'build')
            written_data = {relative: (root / relative).read_bytes() for relative in written}
            times.again.append(_timed_run(generate, root, timeout))
            times.copy.append(_timed_run(['cp', '-r', 'gen', 'copy'], root, timeout))
            times.durable_copy.append(_timed_run(
                ['sh', '-c', 'cp -r gen durable && sync'], root, timeout))
            times.plain.append(write_plainly(root / 'gen', root / 'plain'))
            times.everything.append(write_files(written_data, root / 'everything', sync=True))
            times.written = len(written)
            times.files = len(_files_below(root, 'gen'))
    os.sync()
    return times


def _median_ratio(step: list[float], *reference: list[float]) -> float:
    """Return the median over the rounds of step / (the sum of the reference steps).

    Each ratio is taken within its round: its steps met the disk in the same state.
    """
    return statistics.median(s / sum(r) for s, *r in zip(step, *reference))


def report(components: int, times: CliTimes) -> list[str]:
    """Return the figures and the goals, one line each."""
    listing, first, again = min(times.listing), min(times.first), min(times.again)
    copy, plain = min(times.copy), min(times.plain)
    durable_copy = min(times.durable_copy)

    def met(value: float, goal: float) -> str:
        return 'met' if value <= goal else 'NOT met'

    no_change = _median_ratio(times.again, times.listing)
    first_ratio = _median_ratio(times.first, times.again, times.copy)
    durable_ratio = _median_ratio(times.first, times.again, times.durable_copy)
    floor_ratio = _median_ratio(times.first, times.again, times.everything)
    return [
        f'through the CLI, N={components} ({times.files} files generated; '
        f'{len(times.first)} round(s), each step after a flush of the disk; the goals by the '
        f"median of the rounds' ratios):",
        f'  fastest of the rounds: colcon list {listing:.2f} s; first generation {first:.2f} s; '
        f'no-change generation {again:.2f} s; cp -r of the output {copy:.2f} s, then sync '
        f'{durable_copy:.2f} s; the same files written with open()/write() {plain:.2f} s '
        f'({ratio(plain, copy)} of cp -r)',
        f'  goal P1 no change: no-change generation / colcon list = {no_change:.2f}x '
        f'(goal <= {GOAL_NO_CHANGE}x): {met(no_change, GOAL_NO_CHANGE)}',
        f'  goal P1 first: first generation / (no-change generation + cp -r) = '
        f'{first_ratio:.2f}x (goal <= {GOAL_FIRST}x): {met(first_ratio, GOAL_FIRST)}',
        f'  the same against the durable copy (cp -r, then sync: the output made durable '
        f'as the generation makes it): {durable_ratio:.2f}x',
        f'  the floor: every file the first generation wrote ({times.written}: the packages, '
        f'the implementation files created, the check cache and stamps) written with '
        f'open()/write() then synced, fastest {min(times.everything):.2f} s; first '
        f'generation / (no-change generation + that) = {floor_ratio:.2f}x',
        f'  spread: list {spread(times.listing)}; first {spread(times.first)}; '
        f'no change {spread(times.again)}; cp -r {spread(times.copy)}; '
        f'cp -r + sync {spread(times.durable_copy)}; '
        f'every file written {spread(times.everything)}; '
        f'open/write {spread(times.plain)}',
    ]
