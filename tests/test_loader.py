# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""The loader: plain data, where each node stands, and hostile input."""

from __future__ import annotations

from pathlib import Path
import time

import pytest

from colcon_robmosys.check import load_model_file
from colcon_robmosys.errors import Location, RobmosysError
from colcon_robmosys.model.loader import (
    load_file, load_text, MAX_ALIASED_VALUES, MAX_MODEL_BYTES, MAX_MODEL_DEPTH,
    MAX_MODEL_NODES)

PATH = Path('robmosys.yaml')


def _errors(text: str) -> list[str]:
    """Return the diagnostics of a text that does not load."""
    with pytest.raises(RobmosysError) as info:
        load_text(text, PATH)
    return [str(d) for d in info.value.diagnostics]


def _at(line: int, column: int) -> Location:
    return Location(str(PATH), line, column)


# marks ----------------------------------------------------------------------

DOCUMENT = """\
robmosys: 1
components:
  - name: Talker
    ports:
      pMap: {pattern: push, role: provided}
    functions: [fA, fB]
"""


def test_plain_data():
    loaded = load_text(DOCUMENT, PATH)
    assert loaded.path == PATH
    assert loaded.data == {'robmosys': 1, 'components': [{
        'name': 'Talker',
        'ports': {'pMap': {'pattern': 'push', 'role': 'provided'}},
        'functions': ['fA', 'fB'],
    }]}


def test_value_and_key_marks():
    loaded = load_text(DOCUMENT, PATH)
    assert loaded.location(()) == _at(1, 1)
    assert loaded.location(('robmosys',)) == _at(1, 11)
    assert loaded.location(('robmosys',), key=True) == _at(1, 1)
    # a list item's key is the item itself
    assert loaded.location(('components', 0)) == _at(3, 5)
    assert loaded.location(('components', 0), key=True) == _at(3, 5)
    assert loaded.location(('components', 0, 'name')) == _at(3, 11)
    assert loaded.location(('components', 0, 'ports', 'pMap'),
                           key=True) == _at(5, 7)
    assert loaded.location(
        ('components', 0, 'ports', 'pMap', 'role')) == _at(5, 35)
    assert loaded.location(('components', 0, 'functions', 1)) == _at(6, 21)


def test_location_of_a_missing_node_is_its_closest_parent():
    loaded = load_text(DOCUMENT, PATH)
    assert loaded.location(('components', 0, 'ports', 'pMap', 'qos',
                            'depth')) == _at(5, 13)
    assert loaded.location(('nothing', 'here')) == _at(1, 1)


def test_block_scalar_starts_at_its_first_line():
    text = 'code: |\n\n    x = 1\n    y = 2\nother: >\n  folded\n'
    loaded = load_text(text, PATH)
    assert loaded.data == {'code': '\nx = 1\ny = 2\n', 'other': 'folded\n'}
    # the first line of the text, blank or not, at the block's indentation
    assert loaded.location(('code',)) == _at(2, 5)
    assert loaded.location(('code',), key=True) == _at(1, 1)
    assert loaded.location(('other',)) == _at(6, 3)


# keys -----------------------------------------------------------------------

def test_every_duplicate_key_is_reported_at_once():
    text = 'a: 1\nb: {c: 1, c: 2}\na: 3\n'
    assert _errors(text) == [
        "robmosys.yaml:2:11: error: duplicate key 'c'",
        "robmosys.yaml:3:1: error: duplicate key 'a'",
    ]


@pytest.mark.parametrize('key, kind', [
    ('yes', 'the boolean true'),
    ('on', 'the boolean true'),
    ('off', 'the boolean false'),
    ('No', 'the boolean false'),
    ('~', 'null'),
    ('12', 'a int'),
    ('1.5', 'a float'),
])
def test_key_not_read_as_a_string(key: str, kind: str):
    assert _errors(f'ports:\n  {key}: 1\n') == [
        f"robmosys.yaml:2:3: error: key '{key}' is read as {kind}, "
        'not as a name: quote it']


def test_quoted_keys_are_names():
    assert load_text("'on': 1\n\"yes\": 2\n", PATH).data == {
        'on': 1, 'yes': 2}


def test_merge_keys_are_overridden_not_duplicated():
    text = """\
base: &base {reliability: best_effort, depth: 5}
merged: {<<: *base, depth: 7}
"""
    loaded = load_text(text, PATH)
    assert loaded.data['merged'] == {'reliability': 'best_effort',
                                     'depth': 7}
    # the overriding key and value are where the value comes from
    assert loaded.location(('merged', 'depth')) == _at(2, 28)
    assert loaded.location(('merged', 'depth'), key=True) == _at(2, 21)


def test_a_key_given_twice_beside_a_merge_is_a_duplicate():
    text = 'base: &b {x: 1}\nm: {<<: *b, x: 2, x: 3}\n'
    assert _errors(text) == ["robmosys.yaml:2:19: error: duplicate key 'x'"]


# aliases --------------------------------------------------------------------

def _laughs(levels: int) -> str:
    lines = ['a: &a [lol, lol, lol, lol, lol, lol, lol, lol, lol]']
    names = 'abcdefghijklmnop'
    for previous, name in zip(names, names[1:levels]):
        lines.append(f'{name}: &{name} [' + ', '.join([f'*{previous}'] * 9) +
                     ']')
    return '\n'.join(lines) + '\n'


def test_aliases_share_their_value():
    loaded = load_text(_laughs(5), PATH)  # 9**5 values once expanded
    data = loaded.data
    assert len(data['e']) == 9
    assert data['e'][0] is data['e'][8] is data['d']
    assert data['b'][0][0] == 'lol'


def test_billion_laughs_are_refused_fast():
    start = time.monotonic()
    errors = _errors(_laughs(9))  # 9**9 values once expanded
    assert time.monotonic() - start < 1
    # where the alias that goes past the limit is: in the list of f
    assert errors == [
        f'robmosys.yaml:6:4: error: aliases repeat more than '
        f'{MAX_ALIASED_VALUES} values in all: the model would be too large '
        'once expanded']


def test_billion_laughs_in_a_free_form_value_stop_before_validation(
        tmp_path: Path):
    # a parameter default is not checked by the schema: the laughs would
    # reach the semantic checks, which walk values and print them
    items = ', '.join(f'&l{i} [' + ', '.join([f'*l{i - 1}'] * 9) + ']'
                      for i in range(1, 9))
    path = tmp_path / 'robmosys.yaml'
    path.write_text(f"""\
robmosys: 1
components:
  - {{name: C, package: c_pkg, language: python, license: MIT,
     maintainers: [{{name: A, email: a@example.com}}],
     parameters: {{
       p: {{type: 'int[]', default: [&l0 [1, 2, 3, 4, 5, 6, 7, 8, 9], {items}]}},
       q: {{type: 'int[]', default: *l8}}}}}}
""")
    start = time.monotonic()
    with pytest.raises(RobmosysError) as info:
        load_model_file(path)
    assert time.monotonic() - start < 1
    assert 'aliases repeat more than' in str(info.value)


def test_recursive_alias_is_refused():
    assert _errors('a: &a [1, *a]\n') == [
        'robmosys.yaml:1:4: error: an alias refers to a value that '
        'contains it']


# syntax and encoding --------------------------------------------------------

@pytest.mark.parametrize('text, expected', [
    ('a: [1, 2\n', "2:1: error: invalid YAML: expected ',' or ']', but got "
     "'<stream end>' (while parsing a flow sequence started at 1:4)"),
    ('a: b: c\n', '1:5: error: invalid YAML: mapping values are not allowed '
     'here'),
    ('a: 1\n\tb: 2\n', "2:1: error: invalid YAML: found character '\\t' "
     'that cannot start any token (YAML indents with spaces only)'),
    ('a: *nothing\n', '1:4: error: invalid YAML: found undefined alias '
     "'nothing'"),
    ('a: 1\n---\nb: 2\n', '2:1: error: invalid YAML: expected a single '
     'document in the stream, but found another document'),
    ('a: "\x07"\n', '1:5: error: invalid YAML: the character U+0007 is not '
     'allowed in a YAML file'),
], ids=['unclosed', 'colon', 'tab', 'alias', 'documents', 'control'])
def test_syntax_errors(text: str, expected: str):
    assert _errors(text) == [f'robmosys.yaml:{expected}']


@pytest.mark.parametrize('text', [
    'a: !!python/object/apply:os.system [echo unsafe]\n',
    'a: !!python/name:os.system\n',
    'a: !!python/object:os.system {}\n',
], ids=['sequence', 'scalar', 'mapping'])
def test_python_tags_are_not_constructed(text: str):
    tag = text.split()[1].replace('!!', 'tag:yaml.org,2002:')
    assert _errors(text) == [
        'robmosys.yaml:1:4: error: invalid YAML: could not determine a '
        f"constructor for the tag '{tag}'"]


def test_standard_tags_are_constructed():
    assert load_text('a: !!str 1\nb: !!seq [1]\nc: !!map {d: 1}\n',
                     PATH).data == {'a': '1', 'b': [1], 'c': {'d': 1}}


@pytest.mark.parametrize('text', ['', '\n\n', '# only a comment\n'])
def test_empty_file(text: str):
    assert _errors(text) == [
        'robmosys.yaml:1:1: error: the model file is empty']


def test_non_utf8_bytes(tmp_path: Path):
    path = tmp_path / 'robmosys.yaml'
    path.write_bytes('robmosys: 1\n# café, '.encode() + b'caf\xe9\n')
    with pytest.raises(RobmosysError) as info:
        load_file(path)
    # the column counts characters, not bytes
    assert str(info.value) == (
        f'{path}:2:12: error: the model file is not UTF-8: byte 0xe9 '
        'cannot be decoded (save the file as UTF-8)')


def test_byte_order_mark_is_accepted(tmp_path: Path):
    path = tmp_path / 'robmosys.yaml'
    path.write_bytes(b'\xef\xbb\xbfrobmosys: 1\n')
    assert load_file(path).data == {'robmosys': 1}


def test_huge_file_is_refused_before_reading(tmp_path: Path):
    path = tmp_path / 'robmosys.yaml'
    with path.open('wb') as stream:  # sparse: nothing is written
        stream.truncate(MAX_MODEL_BYTES + 1)
    with pytest.raises(RobmosysError) as info:
        load_file(path)
    assert str(info.value) == (
        f'{path}: error: the model file has {MAX_MODEL_BYTES + 1} bytes, '
        f'more than the {MAX_MODEL_BYTES} a model may have')


def test_huge_model_within_the_size_limit_is_refused_fast(tmp_path: Path):
    """A file just under the byte limit, of tiny values, stops at the node limit."""
    path = tmp_path / 'robmosys.yaml'
    items = ','.join(['x'] * ((MAX_MODEL_BYTES - 100) // 2))
    path.write_text(f'robmosys: 1\ncomponents: [{items}]\n')
    assert path.stat().st_size <= MAX_MODEL_BYTES
    start = time.monotonic()
    with pytest.raises(RobmosysError) as info:
        load_file(path)
    assert time.monotonic() - start < 30
    # four values before the list (mapping, key, value, key), the list, its items
    column = len('components: [') + 1 + 2 * (MAX_MODEL_NODES - 5)
    assert str(info.value) == (
        f'{path}:2:{column}: error: the model holds more than {MAX_MODEL_NODES} values')


def test_deep_nesting_is_refused_not_a_recursion_error():
    text = 'a: ' + '[' * 5000 + ']' * 5000 + '\n'
    assert _errors(text) == [
        f'robmosys.yaml:1:{4 + MAX_MODEL_DEPTH - 1}: error: the model nests mappings and '
        f'lists more than {MAX_MODEL_DEPTH} levels deep']


def test_missing_file(tmp_path: Path):
    path = tmp_path / 'robmosys.yaml'
    with pytest.raises(RobmosysError) as info:
        load_file(path)
    assert str(info.value) == (
        f'{path}: error: cannot read the model file: No such file or '
        'directory')


def test_a_kept_load_is_handed_out_once_and_only_for_the_same_content(tmp_path: Path):
    # discovery's outline keeps what it read for the check of the same
    # process: one parse of each model file, and no reader sees what
    # another changed (the schema fills in defaults)
    path = tmp_path / 'robmosys.yaml'
    path.write_text('robmosys: 1\nservice_definitions: []\n')
    outlined = load_file(path, keep=True)
    checked = load_file(path)
    assert checked is outlined
    checked.data['changed'] = True
    again = load_file(path)
    assert again is not checked and again.data == {'robmosys': 1, 'service_definitions': []}
    load_file(path, keep=True)
    path.write_text('robmosys: 1\n')
    assert load_file(path).data == {'robmosys': 1}
