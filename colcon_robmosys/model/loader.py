# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

"""Load a robmosys.yaml file into plain data plus the location of every node."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Any

import yaml

from colcon_robmosys.errors import Diagnostic, Location, RobmosysError

#: A path into the loaded data: mapping keys and sequence indexes.
NodePath = tuple[str | int, ...]

#: Model files larger than this are refused before parsing.
MAX_MODEL_BYTES = 4 * 1024 * 1024


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


class _Builder:
    """Turn a composed YAML node graph into plain data, recording marks."""

    def __init__(self, path: Path, loader: yaml.SafeLoader, text: str):
        self._display = str(path)
        self._loader = loader
        self._lines = text.split('\n')
        self.value_marks: dict[NodePath, Location] = {}
        self.key_marks: dict[NodePath, Location] = {}
        self.diagnostics: list[Diagnostic] = []
        # aliases share the constructed object instead of expanding anew,
        # which keeps "billion laughs" documents linear in size
        self._built: dict[int, Any] = {}

    def location(self, node: yaml.Node) -> Location:
        mark = node.start_mark
        return Location(self._display, mark.line + 1, mark.column + 1)

    def value_location(self, node: yaml.Node) -> Location:
        """Return where a value starts: a block scalar at its first line."""
        if not isinstance(node, yaml.ScalarNode) or \
                node.style not in ('|', '>'):
            return self.location(node)
        # the text of a block scalar starts on the line after its | or >,
        # so that a line of embedded code maps to a line of the file
        first = node.start_mark.line + 1
        indent = next((len(line) - len(line.lstrip(' '))
                       for line in self._lines[first:node.end_mark.line + 1]
                       if line.strip()), node.start_mark.column)
        return Location(self._display, first + 1, indent + 1)

    def build(self, node: yaml.Node, path: NodePath) -> Any:
        self.value_marks.setdefault(path, self.value_location(node))
        if id(node) in self._built:
            return self._built[id(node)]
        if isinstance(node, yaml.MappingNode):
            result: Any = {}
            self._built[id(node)] = result
            self._loader.flatten_mapping(node)
            for key_node, value_node in node.value:
                key = self._loader.construct_object(key_node, deep=True)
                if not isinstance(key, str):
                    self.diagnostics.append(Diagnostic(
                        self.location(key_node),
                        f'key {key_node.value!r} is read as {_yaml_kind(key)}, '
                        'not as a name: quote it'))
                    continue
                if key in result:
                    self.diagnostics.append(Diagnostic(
                        self.location(key_node), f"duplicate key '{key}'"))
                    continue
                self.key_marks[path + (key,)] = self.location(key_node)
                result[key] = self.build(value_node, path + (key,))
            return result
        if isinstance(node, yaml.SequenceNode):
            items: list[Any] = []
            self._built[id(node)] = items
            for index, item in enumerate(node.value):
                self.key_marks[path + (index,)] = self.location(item)
                items.append(self.build(item, path + (index,)))
            return items
        value = self._loader.construct_object(node, deep=True)
        self._built[id(node)] = value
        return value


def _yaml_problem(exc: yaml.MarkedYAMLError) -> str:
    """Say what PyYAML found, with where the construct it was in began."""
    problem, context = exc.problem, exc.context
    if not problem:
        return context or 'invalid YAML'
    if context and context.startswith('expected'):
        # e.g. 'expected a single document in the stream' + 'but found ...'
        return f'{context}, {problem}'
    mark = exc.context_mark
    if context and mark and mark is not exc.problem_mark:
        return f'{problem} ({context} started at {mark.line + 1}:' \
            f'{mark.column + 1})'
    return problem


def _yaml_kind(value: Any) -> str:
    if isinstance(value, bool):
        return f'the boolean {str(value).lower()}'
    if value is None:
        return 'null'
    return f'a {type(value).__name__}'


def load_text(text: str, path: Path) -> LoadedFile:
    """Parse the text of a model file.

    :raises RobmosysError: for YAML syntax errors and ambiguous keys
    """
    loader = yaml.SafeLoader(text)
    try:
        try:
            node = loader.get_single_node()
        except yaml.MarkedYAMLError as exc:
            mark = exc.problem_mark or exc.context_mark
            line, column = (mark.line + 1, mark.column + 1) if mark else (0, 0)
            raise RobmosysError.at(
                Location(str(path), line, column),
                f'invalid YAML: {_yaml_problem(exc)}') from None
        except yaml.YAMLError as exc:
            raise RobmosysError.in_file(path, f'invalid YAML: {exc}') from None
        if node is None:
            raise RobmosysError.at(
                Location(str(path), 1, 1), 'the model file is empty')
        builder = _Builder(path, loader, text)
        try:
            data = builder.build(node, ())
        except yaml.YAMLError as exc:
            mark = getattr(exc, 'problem_mark', None)
            location = (
                Location(str(path), mark.line + 1, mark.column + 1)
                if mark else Location(str(path)))
            raise RobmosysError.at(
                location, f'invalid YAML: {getattr(exc, "problem", exc)}'
            ) from None
    finally:
        loader.dispose()
    if builder.diagnostics:
        raise RobmosysError(builder.diagnostics)
    return LoadedFile(path, data, builder.value_marks, builder.key_marks)


def load_file(path: Path) -> LoadedFile:
    """Read and parse a model file.

    :raises RobmosysError: if the file cannot be read or parsed
    """
    try:
        size = path.stat().st_size
        if size > MAX_MODEL_BYTES:
            raise RobmosysError.in_file(
                path, f'the model file has {size} bytes, more than the '
                f'{MAX_MODEL_BYTES} a model may have')
        raw = path.read_bytes()
    except OSError as exc:
        raise RobmosysError.in_file(
            path, f'cannot read the model file: {exc.strerror}') from None
    try:
        text = raw.decode('utf-8')
    except UnicodeDecodeError as exc:
        raise RobmosysError.in_file(
            path, f'the model file is not UTF-8 (byte {exc.start})') from None
    return load_text(text, path)
