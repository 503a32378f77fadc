# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""Whatever a model file holds, loading it gives a model or located errors.

Hypothesis feeds bytes, text, YAML-like documents built from the words of the
format, and valid models with random edits to the whole model layer (loader,
schema, typed models, workspace checks). No input may raise anything but
RobmosysError inside the loader, and every diagnostic names its file.
"""

from __future__ import annotations

from pathlib import Path
import tempfile
from typing import Any

from hypothesis import given, HealthCheck, settings, strategies as st
import pytest
import yaml

from colcon_robmosys.check import load_workspace
from colcon_robmosys.check.index import InterfaceIndex
from harness.fake_ament import fake_ament_index

VALID = Path(__file__).parent / 'models' / 'valid'

#: Reproducible in CI: the same examples every run, no example database.
FUZZ = settings(derandomize=True, database=None, deadline=None, max_examples=150,
                suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])

#: The words of the format, so that random documents get past the first check.
WORDS = sorted({
    'robmosys', 'defaults', 'service_definitions', 'components', 'systems', 'package',
    'name', 'language', 'python', 'cpp', 'license', 'maintainers', 'email', 'description',
    'version', 'depends', 'communication_objects', 'queries', 'actions', 'events',
    'request', 'answer', 'goal', 'result', 'feedback', 'fields', 'constants', 'type',
    'value', 'default', 'comment', 'ports', 'pattern', 'role', 'push', 'send', 'query',
    'event', 'action', 'provided', 'required', 'activation', 'qos', 'profile', 'depth',
    'history', 'reliability', 'durability', 'activities', 'period', 'trigger',
    'functions', 'code', 'lifecycle', 'on_configure', 'on_activate', 'parameters',
    'range', 'from', 'to', 'step', 'read_only', 'instances', 'component', 'namespace',
    'after', 'activate', 'connections', 'topic', 'int', 'double', 'string', 'bool',
    'uint8', 'float64', 'string[]', 'int32[3]', 'std_msgs/msg/String', 'demo_msgs/Cell',
    'demo_talker', 'demo_msgs', 'Talker', 'pGrid', 'rCommand', 'fTick', 'Periodic', 'x',
    'talker.pGrid', 'listener.rGrid', 'keep_last', 'reliable', 'sensor_data', 'a@b.c',
})

scalars = st.one_of(
    st.none(), st.booleans(), st.integers(-2 ** 70, 2 ** 70),
    st.floats(allow_nan=True, allow_infinity=True), st.sampled_from(WORDS),
    st.text(max_size=12))
documents = st.recursive(
    scalars,
    lambda children: st.one_of(
        st.lists(children, max_size=4),
        st.dictionaries(st.one_of(st.sampled_from(WORDS), st.text(max_size=6)),
                        children, max_size=5)),
    max_leaves=30)


@pytest.fixture(scope='module')
def index(tmp_path_factory) -> InterfaceIndex:
    return fake_ament_index(tmp_path_factory.mktemp('ament_prefix'))


def _check(data: bytes, index: InterfaceIndex, others: tuple[Path, ...] = ()) -> None:
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / 'robmosys.yaml'
        path.write_bytes(data)
        result = load_workspace([path, *others], index)
        files = {str(p) for p in (path, *others)}
        for diagnostic in result.diagnostics:
            assert diagnostic.location.path in files, diagnostic
            assert diagnostic.message


@settings(FUZZ, max_examples=300)
@given(data=st.binary(max_size=300))
def test_any_bytes(index, data: bytes):
    _check(data, index)


@settings(FUZZ, max_examples=300)
@given(text=st.text(max_size=300))
def test_any_text(index, text: str):
    _check(text.encode('utf-8', errors='surrogatepass'), index)


@FUZZ
@given(document=documents, prefix=st.booleans())
def test_yaml_like_documents(index, document: Any, prefix: bool):
    if prefix:
        document = {'robmosys': 1, 'components': [document]}
    _check(yaml.safe_dump(document, allow_unicode=True).encode('utf-8'), index)


def _paths(data: Any, path: tuple = ()) -> list[tuple]:
    found = [path]
    if isinstance(data, dict):
        for key, value in data.items():
            found += _paths(value, path + (key,))
    elif isinstance(data, list):
        for i, value in enumerate(data):
            found += _paths(value, path + (i,))
    return found


def _edit(data: Any, path: tuple, action: str, value: Any) -> Any:
    if not path:
        return value
    parent = data
    for key in path[:-1]:
        parent = parent[key]
    if action == 'delete':
        del parent[path[-1]]
    elif action == 'rename' and isinstance(parent, dict):
        parent[f'{path[-1]}{value}' if isinstance(value, str) else 'renamed'] = \
            parent.pop(path[-1])
    else:
        parent[path[-1]] = value
    return data


MODELS = sorted(VALID.glob('*.yaml'))


@settings(FUZZ, max_examples=60)
@given(st.data())
def test_valid_models_with_random_edits(index, data):
    model = data.draw(st.sampled_from(MODELS), label='model')
    document = yaml.safe_load(model.read_text())
    for _ in range(data.draw(st.integers(1, 3), label='edits')):
        path = data.draw(st.sampled_from(_paths(document)), label='path')
        action = data.draw(st.sampled_from(['delete', 'replace', 'rename']), label='action')
        if not path:
            action = 'replace'
        document = _edit(document, path, action, data.draw(documents, label='value'))
    others = tuple(m for m in MODELS if m != model)
    _check(yaml.safe_dump(document, allow_unicode=True).encode('utf-8'), index, others)
