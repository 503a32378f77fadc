# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

"""Structural validation against the JSON Schema shipped with the package."""

from __future__ import annotations

from functools import lru_cache
import hashlib
from importlib import resources
import importlib.util
import json
from pathlib import Path
import re
from types import CodeType
from typing import Any, Callable, Iterator

from jsonschema import Draft202012Validator
from jsonschema.exceptions import ValidationError
from jsonschema.validators import extend

from colcon_robmosys.errors import Diagnostic
from colcon_robmosys.model import schema_messages
from colcon_robmosys.model.loader import LoadedFile, NodePath

#: The schema's file, named as its $id ends: the version is that of the
#: format (robmosys: 1), see docs/model-format.md, "Editor support"
SCHEMA_FILE = 'robmosys-1.schema.json'


def schema_path() -> Path:
    """Return the path of the installed JSON Schema file (for editors)."""
    return Path(str(resources.files('colcon_robmosys.model').joinpath(SCHEMA_FILE)))


@lru_cache(maxsize=1)
def schema() -> dict[str, Any]:
    """Return the JSON Schema of robmosys.yaml files."""
    text = schema_path().read_text(encoding='utf-8')
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


#: the compiled schema of this process once made, None in it without
#: fastjsonschema (see _fast_check)
_fast: list[Callable[[Any], Any] | None] = []


#: how compile_fast_check makes its code of fastjsonschema's: a compiled schema
#: kept by an earlier form is made again
_FORM = 2


def compiled_key() -> str | None:
    """Return what the compiled schema depends on, as a digest; None without fastjsonschema.

    The schema, fastjsonschema's version, how this module makes its code and
    the bytecode of this Python: a compiled schema kept under its key
    (check.cache) serves every process of the same four.
    """
    try:
        import fastjsonschema
    except ImportError:
        return None
    digest = hashlib.sha256(schema_path().read_bytes())
    digest.update(f'\0{fastjsonschema.VERSION}\0{_FORM}\0'.encode() +
                  importlib.util.MAGIC_NUMBER)
    return digest.hexdigest()


def compile_fast_check() -> CodeType | None:
    """Compile the schema to Python bytecode; None without fastjsonschema.

    Some 0.2 s: fastjsonschema writes 800 KB of Python (160 KB once its
    refusals are bare), which Python then compiles. Running the code
    (:func:`use_fast_check`) takes a millisecond.
    """
    try:
        import fastjsonschema
    except ImportError:
        return None
    # fastjsonschema knows drafts 4 to 7: the schema uses nothing of 2020-12
    # that draft 7 lacks ($defs is found through the $ref pointers)
    source = fastjsonschema.compile_to_code(dict(_fast_schema(), **{
        '$schema': 'http://json-schema.org/draft-07/schema#'}))
    # the function of the whole schema is the first the code defines
    root = re.search(r'^def (\w+)\(', source, re.MULTILINE)
    assert root is not None, 'fastjsonschema wrote no function'
    # each raise is one line, and only whether a model is valid is asked of this
    # code (jsonschema tells the problems): a bare exception is raised where
    # fastjsonschema's raised one with its message, name, value and definition
    # (the schema's dictionaries, made anew). A valid model has thousands of
    # refusals (the branches of its if, oneOf and anyOf): two thirds of the
    # check's time went there, and four fifths of the code's size
    bare = re.sub(r'^( *)raise JsonSchemaValueException\(.*\)$', r'\1raise _Refused()', source,
                  flags=re.MULTILINE)
    for code in (bare, source):  # as written, should fastjsonschema write otherwise
        try:
            return compile(f'{code}\n{_REFUSED}\n{_ROOT} = {root.group(1)}\n',
                           '<robmosys schema>', 'exec')
        except SyntaxError:
            continue
    raise AssertionError('fastjsonschema wrote code that does not compile')


#: what the code of compile_fast_check raises where fastjsonschema's raised its
#: JsonSchemaValueException (which its handlers catch)
_REFUSED = """
class _Refused(JsonSchemaValueException):
    def __init__(self):
        pass
"""


def _fast_schema() -> dict[str, Any]:
    """Return the schema, with what fastjsonschema checks slowly said another way.

    'not' a keyword: fastjsonschema checks each name against the keywords'
    enum (a list of 124, made anew) and raises where it is not one, which the
    'not' catches: a fifth of the compiled check's time. A pattern that refuses
    them says the same of a string and lets any other value pass, as the enum
    does.
    """
    copied = dict(schema())
    definitions = dict(copied['$defs'])
    keywords = '|'.join(re.escape(word) for word in definitions['reserved_word']['enum'])
    definitions['not_reserved'] = {'pattern': f'^(?!(?:{keywords})\\Z)'}
    copied['$defs'] = definitions
    return copied


#: the name the code of compile_fast_check gives the check of the whole schema
_ROOT = 'robmosys_check'


def use_fast_check(code: CodeType) -> None:
    """Check models with a compiled schema from :func:`compile_fast_check`, in this process."""
    namespace: dict[str, Any] = {}
    exec(code, namespace)  # noqa: S102 - our own schema, compiled by fastjsonschema
    _fast[:] = [namespace[_ROOT]]


def _fast_check() -> Callable[[Any], Any] | None:
    """Return the schema compiled to Python code, None without fastjsonschema.

    It says only whether a model is valid; jsonschema says what every
    problem is, as the messages below translate them, but takes some fifteen
    times as long: it reports the problems of the models fastjsonschema finds
    invalid. Compiled once per process, or
    read from where a build kept it (check.cache).
    """
    if not _fast:
        code = compile_fast_check()
        if code is None:
            _fast[:] = [None]
        else:
            use_fast_check(code)
    return _fast[0]


def warm_fast_check() -> None:
    """Compile the schema now, before this process forks workers that check models."""
    _fast_check()


def fast_check_ready() -> bool:
    """Say whether this process has its compiled schema already (or knows it has none)."""
    return bool(_fast)


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


def _leaves(error: ValidationError) -> Iterator[ValidationError]:
    """Pick the most useful errors below a oneOf/anyOf failure."""
    if error.validator not in ('oneOf', 'anyOf') or not error.context or \
            'errorMessage' in error.schema:
        # an alternative the schema words itself is said as a whole
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
            yield ValidationError(
                f'must be {schema_messages.kinds(kinds)}', validator='type',
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
    said: set[Diagnostic] = set()
    for error in _validator().iter_errors(loaded.data):
        for leaf in _leaves(error):
            path = tuple(error.absolute_path) + tuple(
                leaf.relative_path)[len(error.relative_path):] \
                if leaf is not error else tuple(error.absolute_path)
            message, about_key = schema_messages.message(
                leaf, tuple(path), loaded.data)
            if leaf.validator == 'additionalProperties':
                extra = sorted(set(leaf.instance) - set(
                    leaf.schema.get('properties', {})))
                path = tuple(path) + (extra[0],)
            elif 'propertyNames' in leaf.absolute_schema_path:
                path = tuple(path) + (leaf.instance,)
            elif leaf.validator == 'uniqueItems':
                repeated = schema_messages.repeated_item(leaf.instance)
                if repeated is not None:
                    path = tuple(path) + (repeated[1],)
            diagnostic = Diagnostic(loaded.location(path, key=about_key), message)
            # a name that breaks two rules (a pattern, a keyword) is said once
            if diagnostic not in said:
                said.add(diagnostic)
                diagnostics.append((tuple(path), diagnostic))
    return diagnostics
