# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""libyaml's events give exactly what PyYAML's Python loader gives, only sooner.

The loader reads a model from libyaml's events when PyYAML has libyaml, and
hands any text it does not read that way (an error, an alias, a merge key...)
to the Python loader. Both must give the same data and the same marks, or the
diagnostics of a model would depend on how PyYAML was built.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

from hypothesis import given, HealthCheck, settings, strategies as st
import pytest
import yaml

from colcon_robmosys.errors import RobmosysError
from colcon_robmosys.model import loader
from colcon_robmosys.model.loader import load_text, load_text_completely

TESTS = Path(__file__).parent
#: Every YAML file of the tests: valid and invalid models, the test workspace.
FILES = sorted(p for p in TESTS.parent.glob('*/**/*.yaml')
               if '.venv' not in p.parts and 'build' not in p.parts)
PATH = Path('robmosys.yaml')

FUZZ = settings(derandomize=True, database=None, deadline=None, max_examples=200,
                suppress_health_check=[HealthCheck.too_slow])

needs_libyaml = pytest.mark.skipif(loader.CLoader is None,
                                   reason='PyYAML was built without libyaml')


def _complete(text: str) -> tuple[Any, ...]:
    try:
        loaded = load_text_completely(text, PATH)
    except RobmosysError as exc:
        return ('error', str(exc))
    return (loaded.data, loaded.value_marks, loaded.key_marks)


def _alike(text: str) -> None:
    """Check that the events give what the Python loader gives, where they give anything.

    libyaml takes a few texts that PyYAML's Python parser refuses as invalid
    YAML (a comment right after a block scalar's '|', a tab after a value):
    there libyaml's reading stands. Any other difference is a bug.
    """
    result = _fast(text)
    if result is None:
        return
    expected = _complete(text)
    if expected[0] == 'error' and ': error: invalid YAML: ' in expected[1]:
        return
    assert result == expected


def _fast(text: str) -> tuple[Any, ...] | None:
    """Return what the events give, None where they hand over to the Python loader."""
    builder = loader.FastBuilder(PATH, text)
    try:
        data = builder.build()
    except loader.Unusual:
        return None
    return (data, builder.value_marks, builder.key_marks)


@needs_libyaml
def test_the_test_files_load_alike():
    fast = 0
    assert len(FILES) > 100
    for path in FILES:
        text = path.read_text(encoding='utf-8', errors='replace')
        result = _fast(text)
        if result is not None:
            fast += 1
            assert result == _complete(text), path
    # the models of the tests are read from the events, nearly all of them
    assert fast >= 0.8 * len(FILES)


@needs_libyaml
def test_valid_models_take_the_fast_way():
    for path in sorted((TESTS / 'models' / 'valid').glob('*.yaml')):
        text = path.read_text(encoding='utf-8')
        if '&' not in text and '<<' not in text:
            assert _fast(text) is not None, path


scalars = st.one_of(
    st.none(), st.booleans(), st.integers(-2 ** 70, 2 ** 70),
    st.floats(allow_nan=True, allow_infinity=True), st.text(max_size=8),
    st.sampled_from(['yes', 'on', '~', '1.5', '12', '0x1f', '2001-12-14', '=', '<<',
                     'a: b', '- x', '#', "'", '"', '\t', 'é', '\u2028', '\x85']))
documents = st.recursive(
    scalars,
    lambda children: st.one_of(
        st.lists(children, max_size=4),
        st.dictionaries(st.one_of(st.text(max_size=6), scalars), children, max_size=4)),
    max_leaves=25)


@needs_libyaml
@FUZZ
@given(document=documents, flow=st.sampled_from([None, True, False]),
       style=st.sampled_from([None, '"', "'", '|']), width=st.sampled_from([10, 80]))
def test_dumped_documents_load_alike(document: Any, flow: Any, style: Any, width: int):
    text = yaml.safe_dump(document, default_flow_style=flow, default_style=style,
                          allow_unicode=True, width=width)
    _alike(text)


@needs_libyaml
@FUZZ
@given(text=st.text(alphabet='ab: -[]{},"\'|>\n\t#&*!<=?.1\r\u2028é', max_size=60))
def test_yaml_like_texts_load_alike(text: str):
    _alike(text)


def test_without_libyaml_the_python_loader_does_it_all(monkeypatch):
    texts = [p.read_text(encoding='utf-8') for p in
             sorted((TESTS / 'models' / 'valid').glob('*.yaml'))]
    expected = [_complete(t) for t in texts]
    monkeypatch.setattr(loader, 'CLoader', None)
    for text, result in zip(texts, expected):
        loaded = load_text(text, PATH)
        assert (loaded.data, loaded.value_marks, loaded.key_marks) == result
