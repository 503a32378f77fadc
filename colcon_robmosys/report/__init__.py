# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

"""Machine-readable reports of model diagnostics, for CI pipelines.

The diagnostics of one run, warnings included, each once, as JSON (our own
small format), SARIF 2.1.0 (what code-scanning annotations read) or JUnit
XML (what ``colcon test-result`` and CI test reporters collect). The bare
``file:line:col: error: message`` lines stay on stderr whatever the format.
"""

from __future__ import annotations

from dataclasses import dataclass
import os
from pathlib import Path
import tempfile
from typing import Callable, Iterable

from colcon_robmosys.errors import Diagnostic
from colcon_robmosys.report.formats import json_report, junit_report, sarif_report
from colcon_robmosys.report.formats import Report, TOOL

__all__ = ['FORMATS', 'MATCHER', 'Report', 'report_problem', 'ReportRequest', 'TOOL',
           'write_report']

#: format -> (writer, the suffix of its default file name)
FORMATS: dict[str, tuple[Callable[[Report], bytes], str]] = {
    'json': (json_report, 'json'),
    'sarif': (sarif_report, 'sarif'),
    'junit': (junit_report, 'xml'),
}

#: the GitHub Actions problem matcher of the bare diagnostic lines (docs/ci.md)
MATCHER = Path(__file__).with_name('problem-matcher.json')

#: how much of an existing file is read to tell a report of ours
_HEAD = 4096


@dataclass(frozen=True)
class ReportRequest:
    """Where a run writes its report, and in which format."""

    format: str
    path: Path

    @classmethod
    def of(cls, format_: str | None, path: Path | None) -> 'ReportRequest | None':
        """Return the request of command-line options, or None for no report."""
        if format_ is None:
            return None
        return cls(format_, path or Path(f'robmosys-diagnostics.{FORMATS[format_][1]}'))


def report_problem(path: Path) -> str | None:
    """Return why a report cannot be written to a path, or None.

    A report replaces the report of the last run, and nothing else: a file
    that does not name colcon-robmosys near its start is the user's own.
    """
    if path.is_dir():
        return f'{path}: error: is a folder, not the file of a diagnostics report'
    if path.exists() or path.is_symlink():
        try:
            with path.open('rb') as stream:
                head = stream.read(_HEAD)
        except OSError as error:
            return f'{path}: error: cannot read it: {error.strerror}'
        if TOOL.encode() not in head:
            return (f'{path}: error: the file exists and is no report of {TOOL}: '
                    'it is not replaced (choose another --diagnostics-file)')
    return None


def write_report(request: ReportRequest, files: Iterable[str],
                 diagnostics: Iterable[Diagnostic]) -> None:
    """Write the report of a run: every file checked, every diagnostic once.

    Written to a temporary file beside it and renamed over it, so that a
    reader never sees half a report.

    :raises OSError: where the file cannot be written
    """
    writer, _ = FORMATS[request.format]
    data = writer(Report.of(files, diagnostics))
    folder = request.path.parent
    folder.mkdir(parents=True, exist_ok=True)
    fd, temp = tempfile.mkstemp(prefix=f'.{request.path.name}.', dir=folder)
    try:
        with os.fdopen(fd, 'wb') as stream:
            stream.write(data)
        os.replace(temp, request.path)
    except BaseException:
        os.unlink(temp)
        raise
