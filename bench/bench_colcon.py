# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""Benchmark 2: what colcon costs on robmosys models vs on the same packages written by hand.

Compares two workspaces that give colcon the same packages: one of robmosys models
(synthetic, see ``synthetic.py``), and one of the packages they generate, written
out as ordinary ament_cmake packages (what a team would write by hand to get the
same result). Measured in the same run, alternating the two workspaces:

- ``colcon list`` and ``colcon graph`` on workspaces of ``--list-size`` components
  (with their service definitions and systems): colcon's discovery, which for the
  models means loading and validating every model (or reading the cache of a build);
- a no-op ``colcon build`` (a build after a build, nothing changed) on a workspace of
  ``--build-size`` components that exchange std_msgs/msg/Header (so that no rosidl
  build makes the first builds take long): per package, the models are generated
  again (nothing written), then both sides run the same CMake build and install.

Prints the time of each side and the ratio models / hand-written.

    make bench-colcon                      # or: .venv/bin/python bench/bench_colcon.py
"""

from __future__ import annotations

import argparse
from pathlib import Path
import subprocess
import sys
import tempfile
from typing import Sequence

from benchlib import best, print_end, print_machine, ratio, spread, table, timed
from colcon_robmosys.devtools import ros_env
from synthetic import write_handwritten, write_workspace

SIDES = ('models', 'hand-written')


def colcon(args: list[str], root: Path, timeout: float) -> subprocess.CompletedProcess[str]:
    """Run colcon from this venv in a workspace, on loopback; raise if it fails."""
    env = ros_env.loopback_env(ros_env.free_domain_id())
    result = ros_env.run([str(Path(sys.prefix) / 'bin' / 'colcon'), *args],
                         env=env, cwd=root, timeout=timeout)
    if result.returncode:
        raise RuntimeError(f'colcon {" ".join(args)} failed in {root}:\n'
                           f'{result.stdout}{result.stderr}')
    return result


def make_pair(root: Path, components: int, *, own_messages: bool) -> dict[str, Path]:
    """Write the two workspaces of a comparison; return their roots by side."""
    roots = {side: root / side.replace('-', '') for side in SIDES}
    write_workspace(roots['models'] / 'src', components, own_messages=own_messages)
    write_handwritten(roots['models'] / 'src', roots['hand-written'] / 'src')
    return roots


def listed(root: Path, timeout: float) -> list[str]:
    """Return the names of the packages ``colcon list`` finds."""
    return sorted(line.split('\t')[0] for line in
                  colcon(['list'], root, timeout).stdout.splitlines() if line)


def alternate(roots: dict[str, Path], repeat: int, args: list[str],
              timeout: float) -> dict[str, list[float]]:
    """Time a colcon command on both sides, alternating which goes first."""
    times: dict[str, list[float]] = {side: [] for side in SIDES}
    for index in range(repeat):
        for side in SIDES[::1 if index % 2 == 0 else -1]:
            times[side].append(timed(lambda: colcon(args, roots[side], timeout)))
    return times


def row(what: str, packages: int, times: dict[str, list[float]]) -> list[object]:
    """Return a table row: the best time of each side and their ratio."""
    models, handwritten = best(times['models']), best(times['hand-written'])
    return [what, packages, len(times['models']), f'{models:.2f}', f'{handwritten:.2f}',
            ratio(models, handwritten)]


def main(argv: Sequence[str] | None = None) -> int:
    """Run the benchmark and print its figures."""
    parser = argparse.ArgumentParser(description=__doc__.split('\n\n')[0])
    parser.add_argument('--list-size', type=int, nargs='+', default=[100, 1000],
                        help='components of the colcon list and colcon graph '
                        'workspaces (default: 100 1000)')
    parser.add_argument('--build-size', type=int, default=20,
                        help='components of the colcon build workspace, 0 to build '
                        'nothing (default: 20)')
    parser.add_argument('--repeat', type=int, default=5,
                        help='runs of each command on each side; the fastest counts '
                        '(default: 5)')
    parser.add_argument('--timeout', type=float, default=1800,
                        help='seconds any one colcon run may take (default: 1800)')
    args = parser.parse_args(argv)
    print_machine('colcon overhead: robmosys models vs the same packages written by hand')
    rows, spreads = [], []
    with tempfile.TemporaryDirectory(prefix='robmosys-bench-colcon-') as tmp:
        for size in args.list_size:
            roots = make_pair(Path(tmp) / f'list{size}', size, own_messages=True)
            names = {side: listed(root, args.timeout) for side, root in roots.items()}
            if names['models'] != names['hand-written']:
                raise RuntimeError(f'the two workspaces list different packages: {names}')
            for verb in ('list', 'graph'):
                times = alternate(roots, args.repeat, [verb], args.timeout)
                rows.append(row(f'colcon {verb} ({size} components)',
                                len(names['models']), times))
                spreads.append((f'colcon {verb} ({size})', times))

        if args.build_size:
            roots = make_pair(Path(tmp) / 'build', args.build_size, own_messages=False)
            build = ['build', '--event-handlers', 'console_direct-']
            packages = len(listed(roots['models'], args.timeout))
            first = alternate(roots, 1, build, args.timeout)
            rows.append(row(f'first colcon build ({args.build_size} components)', packages,
                            first))
            times = alternate(roots, args.repeat, build, args.timeout)
            rows.append(row(f'no-op colcon build ({args.build_size} components)', packages,
                            times))
            spreads.append(('no-op colcon build', times))
    print(table(['command', 'packages', 'runs', 'models s', 'hand-written s',
                 'ratio models/hand'], rows))
    print('spread (s):')
    for what, times in spreads:
        for side in SIDES:
            print(f'  {what}, {side}: {spread(times[side])}')
    print_end()
    return 0


if __name__ == '__main__':
    raise SystemExit(main())
