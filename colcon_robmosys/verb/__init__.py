# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

import os
from pathlib import Path
import re

from colcon_robmosys.report import FORMATS
from colcon_robmosys.report import ReportRequest

#: a maintainer as package.xml shows one
MAINTAINER = re.compile(r'\s*(.+?)\s*<([^<>@\s]+@[^<>\s]+)>\s*')


def display_path(path):
    """Return a path as the verbs print it: relative to here where it can be."""
    try:
        return os.path.relpath(path)
    except ValueError:
        return str(path)


def add_diagnostics_arguments(parser):
    """Add the options of a machine-readable report of the model diagnostics."""
    parser.add_argument(
        '--diagnostics-format', choices=sorted(FORMATS),
        help='Also write every model diagnostic of the run, warnings included, '
        'to a report: json, sarif (SARIF 2.1.0, for code scanning) or junit '
        '(JUnit XML, one test case per model file); the compiler-style lines '
        'on stderr stay')
    parser.add_argument(
        '--diagnostics-file', metavar='PATH', type=Path,
        help='Where the report goes (default: robmosys-diagnostics.json, '
        '.sarif or .xml in the current folder); it replaces a report of an '
        'earlier run, never another file')


def diagnostics_request(args):
    """Return the report the command line asks for, or None."""
    return ReportRequest.of(getattr(args, 'diagnostics_format', None),
                            getattr(args, 'diagnostics_file', None))
