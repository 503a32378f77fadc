# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

import os
from pathlib import Path
import re
import sys

from colcon_core.plugin_system import satisfies_version
from colcon_core.verb import VerbExtensionPoint

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


def add_subverbs(parser, *, title, dest):
    """Add the sub-verbs of a verb: the action to add each one's parser to.

    The sub-verb is not required to argparse (see :func:`missing_subverb`):
    colcon-defaults parses the command line once before colcon does, with
    --help silenced and the required arguments relaxed, but only those added
    with ``add_argument``. A subparsers action with ``required=True`` fails that
    first parse, and ``colcon VERB --help`` exited 2 with 'the following
    arguments are required' instead of printing the help (colcon-core#477;
    colcon's own verbs with sub-verbs, ``colcon metadata``, check in ``main``).
    """
    return parser.add_subparsers(title=title, dest=dest)


def missing_subverb(parser, subverbs, args):
    """Return 2 after argparse's usage error if no sub-verb was given, else None.

    :param parser: the verb's parser, given to ``add_arguments``
    :param subverbs: what :func:`add_subverbs` returned for it
    :param args: the parsed command line
    """
    if getattr(args, subverbs.dest, None) is not None:
        return None
    # what argparse prints for a missing required argument, with its code
    parser.print_usage(sys.stderr)
    print(f'{parser.prog}: error: the following arguments are required: '
          f"{{{','.join(subverbs.choices)}}}", file=sys.stderr)
    return 2


class SubverbVerb(VerbExtensionPoint):
    """A verb whose work is one of its sub-verbs: ``colcon VERB SUBVERB ...``."""

    def __init__(self):  # noqa: D107
        super().__init__()
        satisfies_version(VerbExtensionPoint.EXTENSION_POINT_VERSION, '^1.0')
        # the verb's parser and its sub-verbs: main() reports a missing one
        self._parser = self._subverbs = None

    def add_subverbs(self, parser, *, title, dest):
        """Add the sub-verbs (see :func:`add_subverbs`); return the action."""
        self._parser = parser
        self._subverbs = add_subverbs(parser, title=title, dest=dest)
        return self._subverbs

    def missing_subverb(self, args):
        """Return 2 after argparse's usage error if no sub-verb was given, else None."""
        return missing_subverb(self._parser, self._subverbs, args)
