# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

"""The rows of the generators' tables: one template, one output path.

A language backend (:mod:`colcon_robmosys.mapping.backends`) declares its
files with them; :mod:`colcon_robmosys.generators.files` makes files of them.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Callable

from colcon_robmosys.errors import Diagnostic

#: How a backend checks the user's implementation file: (path, text, the
#: class it must define, the functions it must define, where the skeleton
#: that shows them lies) -> the problems, and whether the skeleton shows how
#: to mend them
ImplementationCheck = Callable[[Path, str, str, tuple[str, ...], str],
                               tuple[list[Diagnostic], bool]]


@dataclass(frozen=True)
class Row:
    """A row of a generator's table: one template, one output path.

    ``path`` is formatted with the context's attributes (``{package}``,
    ``{cls}``).
    """

    path: str
    template: str
    #: the attribute of the context that holds the template's context,
    #: if not the whole context (e.g. ``package_xml``)
    part: str = ''
    #: an attribute of the context that must be true for the file to exist
    when: str = ''
    executable: bool = False
    #: render the skeleton flavour of a user file's template
    skeleton: bool = False


@dataclass(frozen=True)
class UserRow:
    """A row of a generator's table for a file the user owns."""

    source_path: str
    template: str
    skeleton_path: str
    when: str = ''
    #: the attribute of the context listing the functions the user writes
    required_functions: str = ''
    required_class: str = ''
    #: what checks the file's text against the model, if anything does
    check: ImplementationCheck | None = None
