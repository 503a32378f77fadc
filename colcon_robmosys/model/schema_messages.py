# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

"""What an error of the JSON Schema says: the check stage's words, not jsonschema's.

The schema decides what is valid; the messages say why in the terms of the
model. A name or a type the schema refuses is explained by the same functions
the file builder uses (names.name_problem, the type parsers), so that a
problem reads the same whichever of the two finds it.
"""

from __future__ import annotations

import json
from typing import Any

from jsonschema.exceptions import ValidationError

from colcon_robmosys.model import names
from colcon_robmosys.model.base import InterfaceKind, Pattern, PATTERN_INTERFACE
from colcon_robmosys.model.fieldtypes import (
    parse_field_type, parse_interface, TypeNameError)
from colcon_robmosys.model.loaded import NodePath

_KIND_NAMES = {
    'object': 'a mapping', 'array': 'a list', 'string': 'a string',
    'integer': 'an integer', 'number': 'a number', 'boolean': 'true or false',
    'null': 'nothing',
}

#: the lists of models of a file -> what a model of each is called
_MODELS = {'service_definitions': 'service definition', 'components': 'component',
           'systems': 'system'}

#: mappings whose keys name things -> what each thing is called
_ENTRIES = {
    'ports': 'port', 'activities': 'activity', 'functions': 'function',
    'parameters': 'parameter', 'instances': 'instance', 'subsystems': 'subsystem',
    'modes': 'mode',
    'communication_objects': 'communication object', 'queries': 'query',
    'actions': 'action', 'events': 'event', 'fields': 'field', 'constants': 'constant',
}

#: the same mappings -> the kind of their keys, for names.name_problem
_NAME_KINDS = dict(
    {k: v for k, v in _ENTRIES.items() if v in names.IDENTIFIER_KINDS},
    communication_objects='interface', queries='interface', actions='interface',
    events='interface', fields='field', constants='constant')

#: validators whose error the schema words itself, with an errorMessage
_WORDED = ('not', 'anyOf', 'oneOf', 'required')


def describe(value: Any) -> str:
    """Show a value of the model in a message."""
    if isinstance(value, bool):
        return 'true' if value else 'false'
    if value is None:
        return 'nothing'
    if isinstance(value, dict):
        return 'a mapping'
    if isinstance(value, list):
        return 'a list'
    if isinstance(value, str):
        return names.shown(value)
    return repr(value)


def repeated_item(items: list[Any]) -> tuple[int, int] | None:
    """Return the indexes of the first entry a list repeats and of its repetition.

    Entries are compared as JSON values (``true`` is not ``1``); None if
    none is found so (``1`` and ``1.0``, which JSON Schema finds equal).
    """
    seen: dict[str, int] = {}
    for index, item in enumerate(items):
        text = json.dumps(item, sort_keys=True, default=str)
        if text in seen:
            return seen[text], index
        seen[text] = index
    return None


def kinds(expected: Any) -> str:
    """Say which kinds of values the schema expects."""
    listed = expected if isinstance(expected, list) else [expected]
    return ' or '.join(_KIND_NAMES.get(k, str(k)) for k in listed)


def _owner(path: NodePath, root: Any) -> tuple[str, int] | None:
    """Return the deepest named thing of the model that holds the node, and its depth.

    Walked from the top, as a key such as 'functions' is a section of a
    component but may also be the name of a port.
    """
    found = None
    if len(path) >= 2 and path[0] in _MODELS and isinstance(path[1], int):
        try:
            package = root[path[0]][path[1]].get('package')
        except (AttributeError, IndexError, KeyError, TypeError):
            package = None
        if isinstance(package, str):
            found = (f'{_MODELS[str(path[0])]} {names.shown(package)}', 2)
    index = 2
    while index + 1 < len(path):
        section, name = path[index], path[index + 1]
        if section in _ENTRIES and isinstance(name, str):
            found = (f'{_ENTRIES[str(section)]} {names.shown(name)}', index + 2)
            index += 2
        elif section == 'qos' and isinstance(name, str) and found is not None and \
                found[1] == index and found[0].startswith('instance '):
            # an instance's QoS overrides are keyed by the component's ports
            found = (f'{found[0]}, port {names.shown(name)}', index + 2)
            index += 2
        else:
            index += 1
    return found


def _subject(path: NodePath) -> str:
    for depth in range(len(path) - 1, -1, -1):
        if isinstance(path[depth], str):
            if depth < len(path) - 1:
                return f"item {int(path[depth + 1]) + 1} of '{path[depth]}'"
            return f"'{path[depth]}'"
    return 'the model'


def _in_owner(path: NodePath, root: Any, text: str) -> str:
    """Say a message about a node inside a named thing, naming the thing."""
    owner = _owner(path, root)
    if owner is None or owner[1] >= len(path) or owner[1] == 2:
        return text
    return f'{owner[0]}: {text}'


def _worded(error: ValidationError, path: NodePath, root: Any) -> str:
    """Say an error the schema words with its errorMessage."""
    text = str(error.schema['errorMessage'])
    owner = _owner(path, root)
    if owner is not None and owner[1] == len(path):
        return f'{owner[0]} {text}'
    subject = f'{_subject(path)} {text}'
    return f'{owner[0]}: {subject}' if owner is not None else subject


def _explained(path: NodePath, root: Any, value: Any, about_key: bool) -> str | None:
    """Say why a name or a type is refused, as the file builder would."""
    if not isinstance(value, str):
        return None
    if about_key:
        kind = _NAME_KINDS.get(str(path[-1])) if path else None
        return names.name_problem(kind, value, names.INTERFACE_SECTIONS.get(
            str(path[-1]), InterfaceKind.MSG)) if kind else None
    if len(path) == 3 and path[0] in _MODELS and path[2] in ('name', 'package'):
        kind = 'package' if path[2] == 'package' else _MODELS[str(path[0])]
        return names.name_problem(kind, value) if kind in (
            'package', 'component', 'system') else None
    owner = _owner(path, root)
    if owner is None:
        return None
    whose, at_owner = owner[0], owner[1] == len(path)
    try:
        if whose.startswith('field ') and (at_owner or path[-1] == 'type'):
            parse_field_type(value, 'own')
        elif whose.startswith('constant ') and path[-1] == 'type':
            parsed = parse_field_type(value, 'own')
            if parsed.message is not None or parsed.array is not None:
                return f'{whose} must have a primitive, non-array type'
        elif whose.startswith('port ') and path[-1] == 'type':
            pattern = root
            for step in path[:-1]:
                pattern = pattern[step]
            parse_interface(value, PATTERN_INTERFACE[Pattern(pattern['pattern'])])
    except TypeNameError as exc:
        return f'{whose}: {exc}'
    except (KeyError, TypeError, ValueError):
        return None
    return None


def message(error: ValidationError, path: NodePath, root: Any) -> tuple[str, bool]:
    """Return the message of a schema error and whether it is about a key.

    :param path: where the error is, in the loaded data
    :param root: the loaded data
    """
    validator = error.validator
    about_key = 'propertyNames' in error.absolute_schema_path
    if validator in ('pattern', 'not'):
        explained = _explained(path, root, error.instance, about_key)
        if explained:
            return explained, about_key
    if validator in _WORDED and isinstance(error.schema, dict) and \
            'errorMessage' in error.schema:
        return _worded(error, path, root), bool(path) and isinstance(path[-1], str)
    if validator == 'additionalProperties':
        allowed = sorted(error.schema.get('properties', {}))
        extra = sorted(set(error.instance) - set(allowed))
        hint = f" (expected one of: {', '.join(allowed)})" if allowed else ''
        return f"unknown key '{extra[0]}' in {_subject(path)}{hint}", True
    if validator == 'uniqueItems':
        # said at the entry that repeats another (schema.structure_problems)
        repeated = repeated_item(error.instance)
        if repeated is not None:
            first, again = repeated
            return _in_owner(path, root, f'{_subject(path)} lists '
                             f'{describe(error.instance[again])} twice (items {first + 1} '
                             f'and {again + 1})'), False
    if validator == 'required':
        missing = error.message.split("'")[1]
        return f"{_subject(path)} lacks the required key '{missing}'", False
    return _in_owner(path, root, _plain(error, path)), about_key


def _plain(error: ValidationError, path: NodePath) -> str:
    """Say an error of one value in the general words of the schema."""
    validator = error.validator
    subject = _subject(path)
    if validator == 'type':
        return f'{subject} must be {kinds(error.validator_value)}, not ' \
            f'{describe(error.instance)}'
    if validator == 'enum':
        options = ', '.join(str(v) for v in error.validator_value)
        return f'{subject} is {describe(error.instance)}, which is not one of: {options}'
    if validator == 'const':
        return f'{subject} must be {error.validator_value}, not {describe(error.instance)}'
    if validator == 'pattern':
        # patternErrorMessage is what VS Code and yaml-language-server show
        text = error.schema.get('patternErrorMessage') or error.schema.get(
            'description') or f'Expected a match of {error.validator_value}'
        hint = f'{text[0].lower()}{text[1:]}'.rstrip('.')
        if 'propertyNames' in error.absolute_schema_path:
            return f'{describe(error.instance)} is not a valid name: {hint}'
        return f'{subject}: {describe(error.instance)} is not valid: {hint}'
    if validator in ('minItems', 'minProperties', 'minLength'):
        return f'{subject} must not be empty'
    bounds = {'minimum': 'at least', 'exclusiveMinimum': 'more than',
              'maximum': 'at most', 'exclusiveMaximum': 'less than'}
    if validator in bounds:
        return f'{subject} must be {bounds[str(validator)]} {error.validator_value}, ' \
            f'not {describe(error.instance)}'
    if validator == 'uniqueItems':
        return f'{subject} lists an item twice'
    return f'{subject}: {error.message}'
