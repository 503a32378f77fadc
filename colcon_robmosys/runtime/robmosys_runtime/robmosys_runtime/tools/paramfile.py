# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""
A ROS 2 parameter file read as rcl_yaml_param_parser reads it, with lines and columns.

The keys above ``ros__parameters`` make the node's name, joined with ``/``
(``robot1: {driver: {ros__parameters: ...}}`` is ``/robot1/driver``); the keys
below it make the parameter's, joined with ``.`` (``pid: {p: 1.0}`` is
``pid.p``). A value is typed the way rcl types it, not the way YAML does: a
quoted scalar or one tagged ``!!str`` is a string, ``true``, ``yes``, ``on``,
``Y`` and their kin are bools, what C's ``strtoll`` (base 0) reads whole is an
integer, what ``strtod`` reads whole a double, anything else a string (``null``
too). A list is an array of one type; rcl refuses lists of mixed types, aliases,
a scalar above ``ros__parameters`` and an empty plain value, and a node cannot
take an empty list or map (no type). Every such problem is reported with its
line and column; the reading goes on past it, so that all of them show at once.
No rclpy: this runs offline.
"""

from __future__ import annotations

from dataclasses import dataclass, field
import difflib
import math
import re
from typing import Any, Dict, List, Optional, Tuple

import yaml

#: the key below which a node's parameters are (rcl compares this many characters)
PARAMS_KEY = 'ros__parameters'
#: the tag of ``!!str``
_STR_TAG = 'tag:yaml.org,2002:str'
_TRUE = {'Y', 'y', 'yes', 'Yes', 'YES', 'true', 'True', 'TRUE', 'on', 'On', 'ON'}
_FALSE = {'N', 'n', 'no', 'No', 'NO', 'false', 'False', 'FALSE', 'off', 'Off', 'OFF'}
#: what rcl reads as nan and infinities before it asks strtod
_SPECIAL = re.compile(r'[+-]?\.(nan|NaN|NAN|inf|Inf|INF)\Z')
_SPACE = '[ \t\n\v\f\r]*'
#: what strtoll reads whole, base 0 (0x: hexadecimal, a leading 0: octal)
_INT = re.compile(_SPACE + r'([+-]?)(0[xX][0-9a-fA-F]+|0[0-7]*|[1-9][0-9]*)\Z')
#: what strtod reads whole: decimal, hexadecimal, infinities, nan
_DOUBLE = re.compile(_SPACE + r'[+-]?(?:(?:[0-9]+\.?[0-9]*|\.[0-9]+)(?:[eE][+-]?[0-9]+)?'
                     r'|(0[xX](?:[0-9a-fA-F]+\.?[0-9a-fA-F]*|\.[0-9a-fA-F]+)(?:[pP][+-]?[0-9]+)?)'
                     r'|(inf(?:inity)?|nan(?:\([0-9A-Za-z_]*\))?))\Z', re.IGNORECASE)
_INT64 = (-2 ** 63, 2 ** 63 - 1)


@dataclass(frozen=True)
class Problem:
    """What is wrong at a place of a parameter file; line and column count from 1."""

    line: int
    column: int
    message: str
    severity: str = 'error'


@dataclass(frozen=True)
class FileValue:
    """A parameter's value in a file, typed as rcl types it."""

    #: the full name, dotted
    name: str
    #: its type: bool, int, double, string or an array of one of them (``int[]``)
    kind: str
    value: Any
    #: as written (the scalar), for messages
    text: str
    #: where its key is
    at: Tuple[int, int]
    #: where its value is; of an array, where each element is
    value_at: Tuple[int, int]
    elements_at: Tuple[Tuple[int, int], ...] = ()


@dataclass(frozen=True)
class NodeEntry:
    """The parameters a file gives the nodes one name matches (``/**``, ``/a/*``, ``/a/b``)."""

    #: with its leading ``/``, as rclcpp and rclpy match it
    name: str
    #: where the key that ends the name is
    at: Tuple[int, int]
    values: Tuple[FileValue, ...]


@dataclass
class ParameterFile:
    """What a file holds, in the order of the file, and what is wrong with it."""

    entries: List[NodeEntry] = field(default_factory=list)
    problems: List[Problem] = field(default_factory=list)


def _at(node: Any) -> Tuple[int, int]:
    return node.start_mark.line + 1, node.start_mark.column + 1


class _Loader(yaml.SafeLoader):
    """Compose nodes that remember whether their tag was written (``!!str``)."""

    def compose_scalar_node(self, anchor: Any) -> Any:
        event = self.peek_event()
        node = super().compose_scalar_node(anchor)
        node.explicit_tag = event.tag not in (None, '!')  # type: ignore[attr-defined]
        return node


def read_text(text: str) -> ParameterFile:
    """Read the text of a parameter file."""
    result = ParameterFile()
    try:
        for event in yaml.parse(text, Loader=yaml.SafeLoader):
            if isinstance(event, yaml.AliasEvent):
                result.problems.append(Problem(
                    *_at(event), f'an alias (*{event.anchor}): rcl does not read '
                    'aliases, and refuses the file'))
        documents = list(yaml.compose_all(text, Loader=_Loader))
    except yaml.MarkedYAMLError as error:
        mark = error.problem_mark or error.context_mark
        line, column = (mark.line + 1, mark.column + 1) if mark is not None else (1, 1)
        problem = ' '.join(p for p in (error.context, error.problem) if p)
        return ParameterFile([], [Problem(line, column, f'not valid YAML: {problem}')])
    except yaml.YAMLError as error:
        return ParameterFile([], [Problem(1, 1, f'not valid YAML: {error}')])
    if result.problems:
        return result
    documents = [d for d in documents if d is not None]
    if not documents:
        result.problems.append(Problem(1, 1, 'not a parameter file: it is empty (a file '
                                       'of ROS 2 parameters maps node names to their '
                                       f"'{PARAMS_KEY}')"))
    for document in documents:
        if not isinstance(document, yaml.MappingNode):
            result.problems.append(Problem(*_at(document), (
                f'not a parameter file: it holds {_kind(document)}, not node names '
                f"mapped to their '{PARAMS_KEY}'")))
            continue
        _read_nodes(document, '', result)
    return result


def _kind(node: Any) -> str:
    if isinstance(node, yaml.SequenceNode):
        return 'a list'
    if isinstance(node, yaml.MappingNode):
        return 'a map'
    return f'the scalar {node.value!r}'


def _join(namespace: str, part: str) -> str:
    """Join node names as rcl's namespace tracker does (no second ``/``)."""
    if not namespace:
        return part
    return namespace + part if namespace.endswith('/') else f'{namespace}/{part}'


def _read_nodes(mapping: Any, namespace: str, result: ParameterFile) -> None:
    for key, value in mapping.value:
        if not isinstance(key, yaml.ScalarNode) or key.value == '':
            result.problems.append(Problem(*_at(key), f'a node name must be a text: '
                                           f'{_kind(key)} cannot be one'))
            continue
        if key.value.startswith(PARAMS_KEY):
            if not namespace:
                result.problems.append(Problem(*_at(key), (
                    f"'{key.value}' has no node name above it: rcl refuses the file")))
                continue
            name = namespace if namespace.startswith('/') else '/' + namespace
            problem = name_problem(name)
            if problem:
                result.problems.append(Problem(*_at(key), f'{name}: {problem}'))
                continue
            values: List[FileValue] = []
            if isinstance(value, yaml.MappingNode):
                _read_parameters(value, '', values, result)
            elif not (isinstance(value, yaml.ScalarNode) and value.value == '' and
                      value.style is None):
                result.problems.append(Problem(*_at(value), (
                    f"'{PARAMS_KEY}' of {name} holds {_kind(value)}: it maps parameter "
                    'names to values')))
            _say_repeated(values, result)
            result.entries.append(NodeEntry(name, _at(key), tuple(values)))
        elif _near_params_key(key.value):
            result.problems.append(Problem(*_at(key), (
                f"'{key.value}': did you mean '{PARAMS_KEY}'? rcl reads it as a node name")))
        elif isinstance(value, yaml.MappingNode):
            _read_nodes(value, _join(namespace, key.value), result)
        else:
            result.problems.append(Problem(*_at(key), (
                f"'{key.value}' holds a value outside any '{PARAMS_KEY}': rcl refuses the "
                f"file (a parameter of {_join(namespace, key.value).rpartition('/')[0] or '/'} "
                f"goes under its '{PARAMS_KEY}')")))


def _say_repeated(values: List[FileValue], result: ParameterFile) -> None:
    """Warn of a parameter an entry sets twice (``pid.p`` and ``pid: {p}``): the last wins."""
    first: Dict[str, FileValue] = {}
    for value in values:
        if value.name in first:
            result.problems.append(Problem(*value.at, (
                f"'{value.name}' is set again here (first on line {first[value.name].at[0]}): "
                'this later value wins'), 'warning'))
        first.setdefault(value.name, value)


def _near_params_key(key: str) -> bool:
    return bool(difflib.get_close_matches(key, [PARAMS_KEY], n=1, cutoff=0.75))


#: a part of a node's namespace or name, as rmw validates it
_NAME_PART = re.compile(r'[A-Za-z_][A-Za-z0-9_]*\Z')


def name_problem(name: str) -> Optional[str]:
    """Return why rcl refuses a node name of a file (``/**`` and ``*`` parts allowed)."""
    if name in ('/**', '/*'):
        return None
    parts = name[1:].split('/')
    if '' in parts:
        return 'an empty part (a repeated or trailing /): rcl refuses the file'
    *namespace, node = parts
    for part in namespace:
        if part not in ('*', '**') and not _NAME_PART.match(part):
            return f"'{part}' is no valid namespace part: rcl refuses the file"
    if node not in ('*', '**') and not _NAME_PART.match(node):
        return f"'{node}' is no valid node name: rcl refuses the file"
    return None


def _read_parameters(mapping: Any, prefix: str, into: List[FileValue],
                     result: ParameterFile) -> None:
    for key, value in mapping.value:
        if not isinstance(key, yaml.ScalarNode) or key.value == '':
            result.problems.append(Problem(*_at(key), (
                f'a parameter name must be a text: {_kind(key)} cannot be one')))
            continue
        name = prefix + key.value
        if isinstance(value, yaml.MappingNode):
            if not value.value:
                result.problems.append(Problem(*_at(value), (
                    f"'{name}' is an empty map: a parameter without a value, which no "
                    'node can take')))
            _read_parameters(value, name + '.', into, result)
        elif isinstance(value, yaml.SequenceNode):
            read = _read_array(name, key, value, result)
            if read is not None:
                into.append(read)
        else:
            typed = rcl_value(value)
            if typed is None:
                result.problems.append(Problem(*_at(key), (
                    f"'{name}' has no value: rcl refuses the file")))
                continue
            into.append(FileValue(name, typed[0], typed[1], value.value, _at(key), _at(value)))


def _read_array(name: str, key: Any, sequence: Any, result: ParameterFile
                ) -> Optional[FileValue]:
    if not sequence.value:
        result.problems.append(Problem(*_at(sequence), (
            f"'{name}' is an empty list: rcl cannot tell its type, and no node can "
            'take it (leave it out to keep the default)')))
        return None
    types: List[str] = []
    values: List[Any] = []
    for element in sequence.value:
        if not isinstance(element, yaml.ScalarNode):
            result.problems.append(Problem(*_at(element), (
                f"'{name}': an element is {_kind(element)}; a parameter's list holds "
                'bools, integers, doubles or strings')))
            return None
        typed = rcl_value(element)
        if typed is None:
            result.problems.append(Problem(*_at(element), (
                f"'{name}': an element has no value: rcl refuses the file")))
            return None
        if types and typed[0] != types[0]:
            result.problems.append(Problem(*_at(element), (
                f"'{name}': {element.value} is {_article(typed[0])} among "
                f'{types[0]}s: rcl refuses a list of mixed types'
                + (' (write every number as a double: 1.0)'
                   if {typed[0], types[0]} == {'int', 'double'} else ''))))
            return None
        types.append(typed[0])
        values.append(typed[1])
    text = '[' + ', '.join(e.value for e in sequence.value) + ']'
    return FileValue(name, types[0] + '[]', values, text, _at(key), _at(sequence),
                     tuple(_at(e) for e in sequence.value))


def _article(type_name: str) -> str:
    return f"{'an' if type_name[0] in 'aeiou' else 'a'} {type_name}"


def rcl_value(scalar: Any) -> Optional[Tuple[str, Any]]:
    """Return a scalar's type and value as rcl reads them, None for no value."""
    text = scalar.value
    if getattr(scalar, 'explicit_tag', False) and scalar.tag == _STR_TAG or \
            scalar.style in ("'", '"'):
        return 'string', text
    if text == '':
        return None
    if text in _TRUE:
        return 'bool', True
    if text in _FALSE:
        return 'bool', False
    number = _INT.match(text)
    if number is not None:
        sign, digits = number.groups()
        base = 16 if digits[:2].lower() == '0x' else 8 if digits.startswith('0') else 10
        value = int(digits, base) * (-1 if sign == '-' else 1)
        if _INT64[0] <= value <= _INT64[1]:
            return 'int', value
    special = _SPECIAL.match(text)
    if special is not None:
        double = float(special.group(1))
        return 'double', -double if text.startswith('-') else double
    number = _DOUBLE.match(text)
    if number is not None:
        hexadecimal, named = number.groups()
        stripped = text.strip()
        double = float.fromhex(stripped) if hexadecimal else \
            float(stripped.split('(')[0]) if named else float(stripped)
        # strtod's overflow is an error to rcl (errno): the text stays a string
        if not math.isinf(double) or named:
            return 'double', double
    return 'string', text
