# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

"""Load a robmosys.yaml file into plain data plus the location of every node."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import yaml

from colcon_robmosys.errors import Diagnostic, Location, RobmosysError
from colcon_robmosys.model.loaded import (
    LoadedFile, MAX_ALIASED_VALUES, MAX_MODEL_BYTES, MAX_MODEL_DEPTH,
    MAX_MODEL_NODES, NodePath, NOT_PRINTABLE, RawData)
from colcon_robmosys.model.loader_fast import CLoader, FastBuilder, Unusual

__all__ = ['LoadedFile', 'load_bytes', 'load_file', 'load_text',
           'load_text_completely', 'MAX_ALIASED_VALUES', 'MAX_MODEL_BYTES',
           'MAX_MODEL_DEPTH', 'MAX_MODEL_NODES', 'NodePath', 'RawData',
           'read_model_bytes']

_MERGE_TAG = 'tag:yaml.org,2002:merge'
_MAP_TAG = 'tag:yaml.org,2002:map'
_SEQ_TAG = 'tag:yaml.org,2002:seq'


class _LimitedLoader(yaml.SafeLoader):
    """A SafeLoader that stops at the size and depth limits of a model."""

    def __init__(self, stream: str, path: Path):
        super().__init__(stream)
        self._path = path
        self._depth = 0
        self._nodes = 0

    def compose_node(self, parent: Any, index: Any) -> Any:
        self._depth += 1
        self._nodes += 1
        if self._depth > MAX_MODEL_DEPTH or self._nodes > MAX_MODEL_NODES:
            mark = self.peek_event().start_mark  # type: ignore[no-untyped-call]
            raise RobmosysError.at(
                Location(str(self._path), mark.line + 1, mark.column + 1),
                f'the model nests mappings and lists more than '
                f'{MAX_MODEL_DEPTH} levels deep'
                if self._depth > MAX_MODEL_DEPTH else
                f'the model holds more than {MAX_MODEL_NODES} values')
        try:
            return super().compose_node(parent, index)
        finally:
            self._depth -= 1


class _Builder:
    """Turn a composed YAML node graph into plain data, recording marks."""

    def __init__(self, path: Path, loader: _LimitedLoader, text: str):
        self._display = str(path)
        self._loader = loader
        self._lines = text.split('\n')
        self.value_marks: dict[NodePath, Location] = {}
        self.key_marks: dict[NodePath, Location] = {}
        self.diagnostics: list[Diagnostic] = []
        # aliases share the constructed object instead of expanding anew,
        # which keeps "billion laughs" documents linear in size
        self._built: dict[int, Any] = {}
        # the expanded number of values of each node built, and the nodes
        # still being built (an alias to one of them would be recursive)
        self._sizes: dict[int, int] = {}
        self._open: set[int] = set()
        self._aliased = 0

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
        # assigned, not set once: a key may override one a merge key gave
        self.value_marks[path] = self.value_location(node)
        if id(node) in self._built:
            return self._alias(node, path)
        if isinstance(node, yaml.CollectionNode) and node.tag not in (
                _MAP_TAG, _SEQ_TAG):
            # tags of scalars are checked when they are constructed
            raise RobmosysError.at(
                self.location(node), 'invalid YAML: could not determine a '
                f"constructor for the tag '{node.tag}'")
        if isinstance(node, yaml.MappingNode):
            result: Any = {}
            self._built[id(node)] = result
            self._open.add(id(node))
            explicit = sum(1 for k, _ in node.value if k.tag != _MERGE_TAG)
            self._loader.flatten_mapping(node)
            # merged pairs come first; later ones override them, as YAML
            # merge keys do, but an explicit key given twice is an error
            merged = len(node.value) - explicit
            explicit_keys: set[str] = set()
            for index, (key_node, value_node) in enumerate(node.value):
                key = self._loader.construct_object(key_node, deep=True)
                if isinstance(key, str) and self._unprintable(key_node, key):
                    continue
                if not isinstance(key, str):
                    self.diagnostics.append(Diagnostic(
                        self.location(key_node),
                        f'key {key_node.value!r} is read as {_yaml_kind(key)}, '
                        'not as a name: quote it'))
                    continue
                if index >= merged:
                    if key in explicit_keys:
                        self.diagnostics.append(Diagnostic(
                            self.location(key_node), f"duplicate key '{key}'"))
                        continue
                    explicit_keys.add(key)
                self.key_marks[path + (key,)] = self.location(key_node)
                result[key] = self.build(value_node, path + (key,))
            self._open.discard(id(node))
            self._sizes[id(node)] = 1 + sum(
                self._sizes.get(id(v), 0) for _, v in node.value)
            return result
        if isinstance(node, yaml.SequenceNode):
            items: list[Any] = []
            self._built[id(node)] = items
            self._open.add(id(node))
            for index, item in enumerate(node.value):
                self.key_marks[path + (index,)] = self.location(item)
                items.append(self.build(item, path + (index,)))
            self._open.discard(id(node))
            self._sizes[id(node)] = 1 + sum(
                self._sizes.get(id(v), 0) for v in node.value)
            return items
        value = self._loader.construct_object(node, deep=True)
        if isinstance(value, str) and self._unprintable(node, value):
            value = NOT_PRINTABLE.sub('\ufffd', value)
        self._built[id(node)] = value
        self._sizes[id(node)] = 1
        return value

    def _unprintable(self, node: yaml.Node, text: str) -> bool:
        """Report a character of a string that YAML does not allow raw."""
        found = NOT_PRINTABLE.search(text)
        if found is None:
            return False
        self.diagnostics.append(Diagnostic(
            self.location(node),
            f'the string holds the character U+{ord(found.group()):04X}, '
            'which a model may not hold: only printable characters, tabs '
            'and line breaks can reach the generated files'))
        return True

    def _alias(self, node: yaml.Node, path: NodePath) -> Any:
        """Return the data of a node met again, through an alias."""
        # a node knows where it was defined, not where an alias repeats it:
        # point at the key or the list that holds the alias
        where = self.key_marks.get(path, self.location(node))
        if path and isinstance(path[-1], int):
            where = self.value_marks.get(path[:-1], where)
        if id(node) in self._open:
            raise RobmosysError.at(
                where, 'an alias refers to a value that contains it')
        self._aliased += self._sizes[id(node)]
        if self._aliased > MAX_ALIASED_VALUES:
            raise RobmosysError.at(
                where, f'aliases repeat more than {MAX_ALIASED_VALUES} '
                'values in all: the model would be too large once expanded')
        return self._built[id(node)]


def _yaml_problem(exc: yaml.MarkedYAMLError) -> str:
    """Say what PyYAML found, with where the construct it was in began."""
    problem, context = exc.problem, exc.context
    if problem and "'\\t'" in problem:
        problem += ' (YAML indents with spaces only)'
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
    if CLoader is not None:
        fast = FastBuilder(path, text)
        try:
            data = fast.build()
        except Unusual:
            pass
        else:
            return LoadedFile(path, data, fast.value_marks, fast.key_marks)
    return load_text_completely(text, path)


def load_text_completely(text: str, path: Path) -> LoadedFile:
    """Parse the text of a model file with PyYAML's Python loader.

    Slower than :func:`load_text`, but every YAML feature and every problem
    goes through it.

    :raises RobmosysError: for YAML syntax errors and ambiguous keys
    """
    try:
        loader = _LimitedLoader(text, path)
    except yaml.reader.ReaderError as exc:
        # the reader checks the whole text at once, before any parsing
        raise RobmosysError.at(
            _offset_location(path, text, exc.position),
            f'invalid YAML: the character U+{exc.character:04X} is not '
            'allowed in a YAML file') from None
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


#: Files loaded for a reader that only read them (discovery's outline), kept
#: for the next load of the same path and bytes (the check of the same
#: process): (path, content) -> what was loaded. Each is handed out once,
#: so that what a reader may change (the schema fills in defaults) is seen
#: by no other; the oldest go first past _KEPT_MAX.
_kept: dict[tuple[str, bytes], LoadedFile] = {}
_KEPT_MAX = 4096


def load_file(path: Path, *, keep: bool = False) -> LoadedFile:
    """Read and parse a model file.

    :param keep: the caller only reads what it gets: keep it for the next
      load of the same content (a model file of 1000 components was parsed
      twice in a first generation, by discovery and by the check)
    :raises RobmosysError: if the file cannot be read or parsed
    """
    return load_bytes(read_model_bytes(path), path, keep=keep)


def read_model_bytes(path: Path) -> bytes:
    """Read a model file, unless it is too large to be a model.

    :raises RobmosysError: if the file cannot be read or is too large
    """
    try:
        size = path.stat().st_size
        if size > MAX_MODEL_BYTES:
            raise RobmosysError.in_file(
                path, f'the model file has {size} bytes, more than the '
                f'{MAX_MODEL_BYTES} a model may have')
        return path.read_bytes()
    except OSError as exc:
        raise RobmosysError.in_file(
            path, f'cannot read the model file: {exc.strerror}') from None


def load_bytes(raw: bytes, path: Path, *, keep: bool = False) -> LoadedFile:
    """Decode and parse the content of a model file.

    :param keep: see :func:`load_file`
    :raises RobmosysError: if it is not UTF-8 or cannot be parsed
    """
    key = (str(path), raw)
    kept = _kept.pop(key, None)
    if kept is not None and not keep:
        return kept
    loaded = _load_bytes(raw, path) if kept is None else kept
    if keep:
        while len(_kept) >= _KEPT_MAX:
            _kept.pop(next(iter(_kept)), None)
        _kept[key] = loaded
    return loaded


def _load_bytes(raw: bytes, path: Path) -> LoadedFile:
    """Decode and parse the content of a model file (see :func:`load_bytes`)."""
    try:
        text = raw.decode('utf-8')
    except UnicodeDecodeError as exc:
        good = raw[:exc.start].decode('utf-8')
        raise RobmosysError.at(
            _offset_location(path, good, len(good)),
            f'the model file is not UTF-8: byte 0x{raw[exc.start]:02x} '
            'cannot be decoded (save the file as UTF-8)') from None
    return load_text(text, path)


def _offset_location(path: Path, text: str, offset: int) -> Location:
    """Return the location of a character of the text."""
    line_start = text.rfind('\n', 0, offset) + 1
    return Location(str(path), text.count('\n', 0, offset) + 1,
                    offset - line_start + 1)
