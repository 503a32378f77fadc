# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""The compiled schema passes a model only where jsonschema finds nothing wrong.

The schema check runs the schema compiled by fastjsonschema first, and asks
jsonschema (whose errors the check translates) only about models it refuses:
a model the compiled schema passed wrongly would skip every message.
"""

from __future__ import annotations

import copy
import functools
from pathlib import Path
from typing import Any

from hypothesis import given, HealthCheck, settings, strategies as st
import pytest
import yaml

from colcon_robmosys.errors import RobmosysError
from colcon_robmosys.model import schema
from colcon_robmosys.model.loader import load_file
from test_loader_fuzz import _edit, _paths, documents, MODELS

MODEL_FILES = sorted((Path(__file__).parent / 'models').glob('*/*.yaml'))
FUZZ = settings(derandomize=True, database=None, deadline=None, max_examples=300,
                suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])

needs_fast = pytest.mark.skipif(schema._fast_check() is None,
                                reason='fastjsonschema is not installed')


def _agree(data: Any) -> bool:
    """Check that the two validators agree on data; return whether it is valid."""
    # jsonschema finds its errors lazily: the first one settles it
    error = next(schema._validator().iter_errors(data), None)
    assert schema.is_valid(data) == (error is None), error
    return error is None


@functools.cache
def _parsed(model: Path) -> Any:
    """Return a model file's data, parsed once: each example edits a deep copy."""
    return yaml.safe_load(model.read_text())


@needs_fast
def test_the_model_files_of_the_tests():
    valid = 0
    for path in MODEL_FILES:
        try:
            data = load_file(path).data
        except RobmosysError:
            continue
        valid += _agree(data)
    assert valid >= 5  # tests/models/valid, and invalid ones that are valid in structure


@needs_fast
@FUZZ
@given(st.data())
def test_valid_models_with_random_edits(data):
    model = data.draw(st.sampled_from(MODELS), label='model')
    document = copy.deepcopy(_parsed(model))
    for _ in range(data.draw(st.integers(1, 3), label='edits')):
        path = data.draw(st.sampled_from(_paths(document)), label='path')
        action = data.draw(st.sampled_from(['delete', 'replace', 'rename']), label='action')
        if not path:
            action = 'replace'
        document = _edit(document, path, action, data.draw(documents, label='value'))
    _agree(document)


@needs_fast
def test_scalars_in_every_place():
    """Scalars of every kind, in turn, in every place of every valid model."""
    values = [True, 1.0, 2.5, -1, 0, 'x\n', '', None, [], {}, 'ok']
    turn = 0
    for model in MODELS:
        original = _parsed(model)
        for path in _paths(original)[1:]:
            turn += 1
            _agree(_edit(copy.deepcopy(original), path, 'replace', values[turn % len(values)]))


@needs_fast
def test_the_compiled_keyword_check_refuses_every_keyword_and_nothing_else():
    import fastjsonschema
    keywords = schema.schema()['$defs']['reserved_word']['enum']
    near = [*(f'{word}{tail}' for word in keywords for tail in ('_', '2', '\n', ' ')),
            *(f'x{word}' for word in keywords), *(word.swapcase() for word in keywords),
            '', 'x', 1, None, [], {}, True]
    near = [value for value in near if value not in keywords]  # 'x' 'or' is 'xor'

    def passes(definitions: dict, value: Any) -> bool:
        check = fastjsonschema.compile({
            '$schema': 'http://json-schema.org/draft-07/schema#',
            '$defs': definitions, '$ref': '#/$defs/not_reserved'})
        try:
            check(value)
        except fastjsonschema.JsonSchemaException:
            return False
        return True
    fast = schema._fast_schema()['$defs']
    assert not [word for word in keywords if passes(fast, word)]
    assert not [value for value in near if not passes(fast, value)]
    # the schema as written says the same (its enum)
    assert not [word for word in keywords if passes(schema.schema()['$defs'], word)]
    assert not [value for value in near if not passes(schema.schema()['$defs'], value)]
