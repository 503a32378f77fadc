# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

"""Structural validation against the JSON Schema shipped with the package."""

from __future__ import annotations

from functools import lru_cache
from importlib import resources
import json
import re
from typing import Any, Callable, Iterator

from jsonschema import Draft202012Validator
from jsonschema.exceptions import ValidationError
from jsonschema.validators import extend

from colcon_robmosys.errors import Diagnostic
from colcon_robmosys.model import names
from colcon_robmosys.model.loader import LoadedFile, NodePath

#: The schema's pattern of names that become C++ and Python identifiers.
IDENTIFIER_PATTERN = '^[A-Za-z][A-Za-z0-9_]*$'

SCHEMA_FILE = 'robmosys.schema.json'

_KIND_NAMES = {
    'object': 'a mapping', 'array': 'a list', 'string': 'a string',
    'integer': 'an integer', 'number': 'a number', 'boolean': 'true or false',
    'null': 'nothing',
}


@lru_cache(maxsize=1)
def schema() -> dict[str, Any]:
    """Return the JSON Schema of robmosys.yaml files."""
    text = resources.files('colcon_robmosys.model').joinpath(
        SCHEMA_FILE).read_text(encoding='utf-8')
    loaded: dict[str, Any] = json.loads(text)
    return loaded


@lru_cache(maxsize=None)
def _compiled(pattern: str) -> re.Pattern[str]:
    # JSON Schema patterns are ECMA-262 regexes, where '$' is the end of the
    # text; Python's '$' also matches before a final newline, which would
    # let 'name\n' pass as a name
    return re.compile(re.sub(r'(?<!\\)\$', r'\\Z', pattern))


def _pattern(validator: Any, pattern: str, instance: Any,
             schema_: dict[str, Any]) -> Iterator[ValidationError]:
    if validator.is_type(instance, 'string') and \
            not _compiled(pattern).search(instance):
        yield ValidationError(f'{instance!r} does not match {pattern!r}')


_Validator = extend(Draft202012Validator, {'pattern': _pattern})


@lru_cache(maxsize=1)
def _validator() -> Any:
    return _Validator(schema())


@lru_cache(maxsize=1)
def _fast_check() -> Callable[[Any], Any] | None:
    """Return the schema compiled to Python code, None without fastjsonschema.

    It says only whether a model is valid, and why at its first problem;
    jsonschema says what every problem is, as the messages below translate
    them, but takes some fifteen times as long: it reports the problems of
    the models fastjsonschema finds invalid.
    """
    try:
        import fastjsonschema
    except ImportError:
        return None
    # fastjsonschema knows drafts 4 to 7: the schema uses nothing of 2020-12
    # that draft 7 lacks ($defs is found through the $ref pointers)
    definition = dict(schema(), **{
        '$schema': 'http://json-schema.org/draft-07/schema#'})
    return fastjsonschema.compile(definition)


def is_valid(data: Any) -> bool:
    """Say whether data passes the schema, as fast as can be."""
    fast = _fast_check()
    if fast is None:
        return bool(_validator().is_valid(data))
    try:
        fast(data)
    except Exception:  # noqa: B902 - any failure: let jsonschema tell
        return False
    return True


def _describe(value: Any) -> str:
    if isinstance(value, bool):
        return 'true' if value else 'false'
    if value is None:
        return 'nothing'
    if isinstance(value, dict):
        return 'a mapping'
    if isinstance(value, list):
        return 'a list'
    if isinstance(value, str):
        # a newline or another invisible character is shown escaped
        return f"'{value}'" if value.isprintable() else repr(value)
    return repr(value)


def _subject(path: tuple[Any, ...]) -> str:
    for depth in range(len(path) - 1, -1, -1):
        if isinstance(path[depth], str):
            if depth < len(path) - 1:
                return f"item {path[depth + 1] + 1} of '{path[depth]}'"
            return f"'{path[depth]}'"
    return 'the model'


def _pattern_hint(schema_: dict[str, Any]) -> str:
    """Say what a string must look like, as the schema explains it."""
    # patternErrorMessage is what VS Code and yaml-language-server show
    text = schema_.get('patternErrorMessage') or schema_.get(
        'description') or f"Expected a match of {schema_.get('pattern')}"
    return f'{text[0].lower()}{text[1:]}'.rstrip('.')


def _message(error: ValidationError) -> tuple[str, bool]:
    """Return the message of a schema error and whether it is about a key."""
    path = tuple(error.absolute_path)
    validator = error.validator
    if validator == 'additionalProperties':
        allowed = sorted(error.schema.get('properties', {}))
        extra = sorted(set(error.instance) - set(allowed))
        hint = f" (expected one of: {', '.join(allowed)})" if allowed else ''
        return f"unknown key '{extra[0]}' in {_subject(path)}{hint}", True
    if validator == 'not' and 'errorMessage' in error.schema:
        # a key that was removed from the format: say where it went
        return error.schema['errorMessage'], True
    if validator == 'required':
        missing = error.message.split("'")[1]
        return f"{_subject(path)} lacks the required key '{missing}'", False
    if validator == 'type':
        expected = error.validator_value
        kinds = expected if isinstance(expected, list) else [expected]
        wanted = ' or '.join(_KIND_NAMES.get(k, str(k)) for k in kinds)
        return (f'{_subject(path)} must be {wanted}, not '
                f'{_describe(error.instance)}'), False
    if validator == 'enum':
        options = ', '.join(str(v) for v in error.validator_value)
        return (f'{_subject(path)} is {_describe(error.instance)}, which is '
                f'not one of: {options}'), False
    if validator == 'const':
        return (f'{_subject(path)} must be {error.validator_value}, not '
                f'{_describe(error.instance)}'), False
    if validator == 'pattern' and 'propertyNames' in \
            error.absolute_schema_path:
        problems = names.identifier_problems(str(error.instance)) \
            if error.validator_value == IDENTIFIER_PATTERN else []
        # every problem of the name at once, where we know them
        reason = f'it {names.join_problems(problems)}' if problems else \
            _pattern_hint(error.schema)
        return f'{_describe(error.instance)} is not a valid name: {reason}', \
            True
    if validator == 'pattern':
        return (f'{_subject(path)}: {_describe(error.instance)} is not valid: '
                f'{_pattern_hint(error.schema)}'), False
    if validator == 'propertyNames':
        return (f'{_describe(error.instance)} is not a valid name: '
                f"{error.schema.get('description', 'invalid name')}"), True
    if validator in ('minItems', 'minProperties', 'minLength'):
        return f'{_subject(path)} must not be empty', False
    if validator in ('minimum', 'exclusiveMinimum'):
        bound = error.validator_value
        relation = 'at least' if validator == 'minimum' else 'more than'
        return (f'{_subject(path)} must be {relation} {bound}, not '
                f'{_describe(error.instance)}'), False
    if validator == 'uniqueItems':
        return f'{_subject(path)} lists an item twice', False
    return f'{_subject(path)}: {error.message}', False


def _leaves(error: ValidationError) -> Iterator[ValidationError]:
    """Pick the most useful errors below a oneOf/anyOf failure."""
    if error.validator not in ('oneOf', 'anyOf') or not error.context:
        yield error
        return
    # the alternative that got furthest into the document explains best
    deepest = max(len(e.absolute_path) for e in error.context)
    candidates = [e for e in error.context
                  if len(e.absolute_path) == deepest]
    if deepest == len(error.absolute_path):
        # no alternative matched even the kind of node: say what it must be
        kinds = [e.validator_value for e in error.context
                 if e.validator == 'type']
        if kinds and len(kinds) == len(error.context):
            wanted = ' or '.join(_KIND_NAMES.get(k, str(k)) for k in kinds)
            yield ValidationError(
                f'must be {wanted}', validator='type',
                validator_value=kinds, instance=error.instance,
                path=error.relative_path, schema=error.schema)
            return
        candidates = [e for e in candidates if e.validator != 'type'] or \
            candidates
    for candidate in candidates[:1]:
        yield from _leaves(candidate)


def check_structure(loaded: LoadedFile) -> list[Diagnostic]:
    """Check a loaded file against the schema; return every problem."""
    return [d for _, d in structure_problems(loaded)]


def structure_problems(loaded: LoadedFile
                       ) -> list[tuple[NodePath, Diagnostic]]:
    """Check a loaded file against the schema; return every problem and its node."""
    if is_valid(loaded.data):
        return []
    diagnostics = []
    for error in _validator().iter_errors(loaded.data):
        for leaf in _leaves(error):
            path = tuple(error.absolute_path) + tuple(
                leaf.relative_path)[len(error.relative_path):] \
                if leaf is not error else tuple(error.absolute_path)
            message, about_key = _message(leaf)
            if about_key and leaf.validator == 'additionalProperties':
                extra = sorted(set(leaf.instance) - set(
                    leaf.schema.get('properties', {})))
                path = tuple(path) + (extra[0],)
            elif about_key and leaf.validator == 'not':
                pass  # the path of the error is the key itself
            elif about_key:
                path = tuple(path) + (leaf.instance,)
            diagnostics.append((tuple(path), Diagnostic(
                loaded.location(path, key=about_key), message)))
    return diagnostics
