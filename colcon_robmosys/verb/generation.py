# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

"""The generation of the selected packages: in this process, or shared by forked ones.

Planning and rendering are Python's CPU time, and writing the files is the
kernel's: one process keeps one core busy. Above a few dozen model files the
verb forks workers (``--parallel-workers``, as ``colcon build`` has), each
generating the packages of its share of the model files from start to end,
as one process does: plan, create the missing implementation files, render,
write, made durable together (generators/durable.py), stamp; the last share
is this process's own. A model file's packages stay in one share: they read
the same folders of the user's. No thread runs beside the verb's (a fork
copies only the calling thread).

What the run prints is the same whichever way: each worker records its lines,
and this process prints them in the order one process would have.
"""

from __future__ import annotations

from dataclasses import dataclass
from dataclasses import field
from functools import partial
import os
from pathlib import Path

from colcon_robmosys.check.forked import available_cpus
from colcon_robmosys.check.forked import fork_map
from colcon_robmosys.check.forked import MIN_FILES_PER_WORKER
from colcon_robmosys.errors import print_diagnostics
from colcon_robmosys.errors import RobmosysError
from colcon_robmosys.generators import create_missing_user_files
from colcon_robmosys.generators import Durable
from colcon_robmosys.generators import fingerprint
from colcon_robmosys.generators import generate_package
from colcon_robmosys.generators import plan_package
from colcon_robmosys.generators import unchanged_package
from colcon_robmosys.mapping.common import RUNTIME_PACKAGE
from colcon_robmosys.verb import display_path

#: When a line is printed: the packages found unchanged and the models that
#: cannot be planned, then the implementation files created, then the
#: packages generated.
PLANNED, CREATED, GENERATED = range(3)


@dataclass(frozen=True)
class Package:
    """A selected package to generate."""

    name: str
    #: the model file it comes from
    model_file: str
    #: where it goes (None: only its missing implementation files are created)
    out: Path | None
    #: whether its descriptor depends on robmosys_runtime
    uses_runtime: bool


@dataclass
class Outcome:
    """What a generation found and has to print."""

    #: (when, package index, line or diagnostics) in the order they came
    lines: list[tuple[int, int, str | tuple]] = field(default_factory=list)
    found: list = field(default_factory=list)
    status: int = 0
    uses_runtime: bool = False

    def fail(self, when, index, diagnostics):
        """Record the errors that stop a package."""
        self.lines.append((when, index, tuple(diagnostics)))
        self.found += diagnostics
        self.status = 1

    def merge(self, other):
        """Add the outcome of another share of the packages."""
        self.lines += other.lines
        self.found += other.found
        self.status = max(self.status, other.status)
        self.uses_runtime = self.uses_runtime or other.uses_runtime

    def print(self):
        """Print the lines in the order one process generating everything would."""
        # stable: a package's lines of one kind keep their order
        for _, _, line in sorted(self.lines, key=lambda entry: entry[:2]):
            if isinstance(line, str):
                print(line)
            else:
                print_diagnostics(line)


def generate_packages(result, packages, stamps, workers):
    """Generate the packages; print what one process would; return the outcome.

    :param result: the check stage's result
    :param packages: the selected :class:`Package` s, in the order to print them
    :param stamps: the :class:`~colcon_robmosys.generators.StampStore` of the run
    :param workers: the most processes to generate in at once
    """
    packages = tuple(packages)
    outcome = Outcome()
    # what to generate: a package whose inputs have not changed since its
    # stamp is neither planned nor rendered again
    todo = []
    for index, package in enumerate(packages):
        inputs = fingerprint(result, package.name, standalone=True)
        report = None if package.out is None else \
            unchanged_package(package.out, stamps, inputs)
        if report is None:
            todo.append((index, inputs))
            continue
        outcome.lines.append((PLANNED, index, said(package.name, package.out, report)))
        outcome.uses_runtime = outcome.uses_runtime or package.uses_runtime
    for share in fork_map(partial(_generate, result, packages, stamps),
                          _shares(packages, todo, workers)):
        outcome.merge(share)
    outcome.print()
    return outcome


def parallel_workers(requested):
    """Return how many workers to use: the CPUs this process may run on, by default."""
    return available_cpus() if requested is None else max(1, requested)


def _shares(packages, todo, workers):
    """Split the packages to generate between the workers, whole model files, even work.

    The size of a model file stands for its work; the largest go first, each
    to the worker with the least so far.

    :param todo: (index, fingerprint) of each package to generate
    :returns: each worker's part of todo, in order
    """
    files = {}
    for entry in todo:
        files.setdefault(packages[entry[0]].model_file, []).append(entry)
    workers = min(workers, len(files) // MIN_FILES_PER_WORKER)
    if workers < 2:
        return [todo]
    shares = [[] for _ in range(workers)]
    loads = [0] * workers
    for size, model_file in sorted(((-_size(f), f) for f in files)):
        least = loads.index(min(loads))
        shares[least] += files[model_file]
        loads[least] -= size
    return [sorted(share) for share in shares]


def _size(path):
    """Return the size of a file, 0 if it cannot be read."""
    try:
        return os.stat(path).st_size
    except OSError:
        return 0


def _generate(result, packages, stamps, share):
    """Generate a share of the packages, as one process generates all of them.

    :param share: (index, fingerprint) of each package
    """
    outcome = Outcome()
    created, generating = Durable(), Durable()
    todo = []
    #: an implementation file -> the package that creates it
    creator = {}
    for index, inputs in share:
        package = packages[index]
        try:
            plan = plan_package(result.workspace, package.name)
            create_missing_user_files(plan, created)
        except RobmosysError as error:
            outcome.fail(PLANNED, index, error.diagnostics)
            continue
        todo.append((index, plan, inputs))
        creator.update((plan.model_dir / f.source_path, index) for f in plan.user_files)
    # the user's files, made durable together, before the packages read them
    for path in created.commit():
        outcome.lines.append(
            (CREATED, creator[path], f'created {display_path(path)}: yours to fill in'))
    try:
        for index, plan, inputs in todo:
            out = packages[index].out
            try:
                if out is not None:
                    # output the user keeps (it may be under version control),
                    # unlike the build tree: made durable
                    outcome.lines.append((GENERATED, index, said(plan.name, out, generate_package(
                        plan, out, durable=generating, stamps=stamps,
                        fingerprint=inputs))))
                outcome.uses_runtime = outcome.uses_runtime or RUNTIME_PACKAGE in plan.depends
            except RobmosysError as error:
                outcome.fail(GENERATED, index, error.diagnostics)
    finally:
        generating.commit()
    return outcome


def said(package, out, report):
    """Return the line that says what the generation of a package wrote."""
    return (f'generated {package} in {display_path(out)}: '
            f'{len(report.written)} written, '
            f'{len(report.unchanged)} unchanged, '
            f'{len(report.removed)} removed')
