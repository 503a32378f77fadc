# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

"""Loaded model data: its nodes, their locations, and the limits of a model."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
import re
from typing import Any

from colcon_robmosys.errors import Location

#: A path into the loaded data: mapping keys and sequence indexes.
NodePath = tuple[str | int, ...]

#: A mapping of the loaded data, structurally checked by the schema.
RawData = dict[str, Any]

#: Model files larger than this are refused before parsing. PyYAML parses
#: some 150 kB a second: a megabyte keeps the worst case to seconds, and is
#: far more than a model of even a large package needs.
MAX_MODEL_BYTES = 1024 * 1024

#: How many values (mappings, lists, scalars) a model file may hold: about
#: four seconds of parsing, however short the values are.
MAX_MODEL_NODES = 100_000

#: How deeply mappings and lists may nest: a model nests some ten levels;
#: thousands would exhaust Python's stack in the YAML composer.
MAX_MODEL_DEPTH = 64

#: How many values aliases may repeat in all: the data is shared, but every
#: later step (validation, messages, generated files) walks it expanded.
MAX_ALIASED_VALUES = 100_000

#: What YAML allows in a file (YAML 1.1, 5.1): an escape in a quoted
#: string could still produce anything else, which no generated file can
#: carry (XML has no NUL, UTF-8 no lone surrogate).
NOT_PRINTABLE = re.compile(
    '[^\t\n\r\x20-\x7e\x85\xa0-\ud7ff\ue000-\ufffd\U00010000-\U0010ffff]')


@dataclass(frozen=True)
class LoadedFile:
    """The plain data of one model file and where each of its nodes stands."""

    path: Path
    data: Any
    value_marks: dict[NodePath, Location]
    key_marks: dict[NodePath, Location]

    def location(self, node_path: NodePath, *, key: bool = False) -> Location:
        """Return the location of a node, or of the closest known parent.

        :param key: point at the mapping key of the node instead of its value
        """
        marks = self.key_marks if key else self.value_marks
        path = tuple(node_path)
        while path:
            if path in marks:
                return marks[path]
            path = path[:-1]
        return self.value_marks.get((), Location(str(self.path), 1, 1))
