# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

"""Diagnostics of colcon-robmosys: one base exception, compiler-style text."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
import sys
from typing import Iterable, TextIO


@dataclass(frozen=True, order=True)
class Location:
    """A place in a model file; line and column count from 1."""

    path: str
    line: int = 0
    column: int = 0

    def __str__(self) -> str:
        if not self.line:
            return self.path
        return f'{self.path}:{self.line}:{self.column}'


@dataclass(frozen=True, order=True)
class Diagnostic:
    """One problem found in a model, formatted like a compiler message."""

    location: Location
    message: str
    severity: str = 'error'

    def __str__(self) -> str:
        return f'{self.location}: {self.severity}: {self.message}'


class RobmosysError(Exception):
    """The one exception colcon-robmosys raises for bad input.

    It carries every problem found, so that a user sees all of them at once.
    """

    def __init__(self, diagnostics: Iterable[Diagnostic]):
        self.diagnostics = tuple(sorted(set(diagnostics)))
        super().__init__('\n'.join(str(d) for d in self.diagnostics))

    def __reduce__(self) -> tuple[type, tuple[tuple[Diagnostic, ...]]]:
        # pickled with its diagnostics (from a forked worker, check/forked.py),
        # not with the text they make
        return type(self), (self.diagnostics,)

    @classmethod
    def at(cls, location: Location, message: str) -> 'RobmosysError':
        """Create an error with a single diagnostic."""
        return cls([Diagnostic(location, message)])

    @classmethod
    def in_file(cls, path: Path | str, message: str) -> 'RobmosysError':
        """Create an error about a whole file."""
        return cls.at(Location(str(path)), message)


#: What :func:`print_diagnostics` printed in this process.
_printed: set[Diagnostic] = set()


def print_diagnostics(diagnostics: Iterable[Diagnostic],
                      stream: TextIO | None = None) -> int:
    """Print each diagnostic not printed yet as one bare compiler-style line.

    One colcon invocation meets a model error in several places (discovery,
    the build task of each package of the file, the verb); editors and CI
    problem matchers (GCC format) want it once, without a logger prefix.

    :returns: how many lines were printed
    """
    stream = sys.stderr if stream is None else stream
    fresh = sorted(set(diagnostics) - _printed)
    for diagnostic in fresh:
        print(diagnostic, file=stream)
    _printed.update(fresh)
    if fresh:
        stream.flush()
    return len(fresh)
