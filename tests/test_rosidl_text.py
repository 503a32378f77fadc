# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""Model text in an interface package reads back from what rosidl built.

Arbitrary printable text (backslashes, quotes, C comment delimiters, newlines,
non-ASCII) goes into every free-text slot of a service definition: the
descriptions and comments that rosidl copies into its C headers, string
defaults and constants that the built Python message gives back. Either the
check refuses the text with the model's line, for a reason that holds, or
real rosidl builds the package and every value reads back exactly.
"""

from __future__ import annotations

import json
from pathlib import Path
import re
import shutil
import sys

from hypothesis import example, given
from hypothesis import HealthCheck, settings, strategies as st
import pytest
import yaml

from colcon_robmosys.check import load_workspace
from colcon_robmosys.devtools import ros_env
from colcon_robmosys.model.fieldtypes import interface_comment_problem
from conftest import colcon, requires_ros

pytestmark = [requires_ros, pytest.mark.integration]

PACKAGE = 'text_msgs'
MESSAGE = 'Text'

#: printable text of any script, with the characters every escaping meets
TEXT = st.lists(
    st.one_of(st.sampled_from(['\\', '"', "'", '*/', '/*', '#', '=', '\n', '??/', ' ']),
              st.characters(blacklist_categories=('Cc', 'Cs', 'Zl', 'Zp'))),
    min_size=1, max_size=12).map(''.join)


def _comment_lines(text: str) -> list[str]:
    """Return the comment lines text becomes (blank edges and line ends dropped)."""
    return [line.rstrip() for line in text.strip().splitlines()]


def value_of(text: str) -> str:
    """Return the text as a string value, or a plain one where .msg cannot carry it.

    The .msg format has no escape for '#', '=' and line ends in a value: the
    check refuses them (tests/models/invalid); every other text is carried.
    """
    return text if text.isprintable() and not set(text) & set('#=') else 'plain'


def item_of(text: str) -> str:
    """Return the text as an item of a string array default, or a plain one."""
    plain = text.isascii() and text.isprintable() and text == text.strip()
    return text if plain and not set(text) & set('"\',[]\\#=') else 'plain'


def _message(texts: list[str], array_items: list[str]) -> dict:
    fields = {f'f{i}': {'type': 'string', 'default': value_of(text), 'comment': text}
              for i, text in enumerate(texts)}
    fields['items'] = {'type': 'string[]', 'default': [item_of(t) for t in array_items]}
    constants = {f'C{i}': {'type': 'string', 'value': value_of(text), 'comment': text}
                 for i, text in enumerate(texts)}
    return {'description': texts[0], 'fields': fields, 'constants': constants}


def _model(texts: list[str], array_items: list[str], package: str = PACKAGE) -> dict:
    return _package({MESSAGE: _message(texts, array_items)}, package)


def _package(messages: dict, package: str = PACKAGE) -> dict:
    return {'robmosys': 1, 'service_definitions': [{
        'package': package, 'license': 'Apache-2.0',
        'maintainers': [{'name': 'A', 'email': 'a@example.com'}],
        'communication_objects': messages}]}


def _write(path: Path, model: dict) -> Path:
    path.parent.mkdir(parents=True)
    path.write_text(yaml.safe_dump(model, allow_unicode=True), encoding='utf-8')
    return path


def _refusal_holds(message: str, texts: list[str]) -> bool:
    """Say whether a refusal names a reason that one of the texts really has."""
    return 'C comment' in message and any(interface_comment_problem(t) for t in texts)


def _read_back(install: Path, messages: list[str], domain_id: int) -> dict:
    """Return the defaults and constants of each built Python message."""
    code = (f'import json\nimport {PACKAGE}.msg\nvalues = {{}}\n'
            f'for name in {messages!r}:\n'
            f'    M = getattr({PACKAGE}.msg, name)\n'
            '    m = M()\n'
            '    values[name] = {\n'
            '        "fields": {n: getattr(m, n) for n in m.get_fields_and_field_types()},\n'
            '        "constants": {n: getattr(M, n) for n in dir(M)\n'
            '                      if n[0] == "C" and n[1:].isdigit()}}\n'
            'print(json.dumps(values))')
    env = ros_env.workspace_env(install, ros_env.loopback_env(domain_id))
    result = ros_env.run([sys.executable, '-c', code], env=env, timeout=60)
    assert result.returncode == 0, result.stderr
    return json.loads(result.stdout.splitlines()[-1])


def _header_comments(install: Path, message: str) -> dict[str, list[str]]:
    """Return the comment of the struct, of each constant and of each member.

    rosidl_generator_c writes them into the message's C header: the struct's
    and the constants' inside ``/** */``, the members' after ``///``.
    """
    header = (install / PACKAGE / 'include' / PACKAGE / PACKAGE / 'msg' / 'detail' /
              f'{message.lower()}__struct.h').read_text(encoding='utf-8')
    comments = {}
    for block, name in re.findall(
            r'/\*\*\n((?:  \*.*\n)*) \*/\n(?:static const .*__(C\d+) =|typedef struct)',
            header):
        comments[name or 'struct'] = [re.sub(r'^  \* ?', '', line)
                                      for line in block.splitlines()]
    for block, name in re.findall(r'((?:  ///.*\n)*)  \S.* (\w+);\n', header):
        comments[name] = [re.sub(r'^  /// ?', '', line) for line in block.splitlines()]
    return comments


def _cases() -> list[tuple[list[str], list[str]]]:
    """Return what hypothesis draws (derandomized: the same cases each run)."""
    cases = []

    @settings(max_examples=8, deadline=None, derandomize=True, database=None,
              suppress_health_check=[HealthCheck.too_slow])
    @given(texts=st.lists(TEXT, min_size=2, max_size=6),
           array_items=st.lists(TEXT, min_size=1, max_size=3))
    # the hard cases, whatever hypothesis draws: each escaping and non-ASCII
    @example(texts=['back\\slash and "quotes" /* ??/ end\nsecond line', 'grüß 日本 😀 \\ x'],
             array_items=['plain', 'words'])
    def draw(texts: list[str], array_items: list[str]) -> None:
        cases.append((texts, array_items))
    draw()
    return cases


def test_text_reads_back_from_the_built_package(tmp_path):
    """
    Every case hypothesis draws is a message of one package, built once by colcon.

    Each case the check refuses is a package of its own in a second workspace:
    its build must refuse every one with the check's lines, in one run.
    """
    accepted, refused = {}, []
    for number, (texts, array_items) in enumerate(_cases()):
        path = _write(tmp_path / 'refused' / 'src' / f'case_{number}' / 'robmosys.yaml',
                      _model(texts, array_items, f'case_{number}_msgs'))
        errors = [d for d in load_workspace([path]).errors if d.location.path == str(path)]
        if not errors:
            shutil.rmtree(path.parent)
            accepted[f'{MESSAGE}{number}'] = (texts, array_items)
            continue
        # refused: at the model's line, for a reason the text has
        for error in errors:
            assert error.location.line > 0, error
            assert _refusal_holds(error.message, texts), error
        refused.extend(errors)
    assert accepted, 'every case drawn was refused: the read back would prove nothing'
    if refused:
        built = colcon(['build'], cwd=tmp_path / 'refused')
        assert built.returncode != 0
        for error in refused:
            assert str(error) in built.stderr, built.stderr
    _write(tmp_path / 'ws' / 'src' / PACKAGE / 'robmosys.yaml', _package(
        {name: _message(*case) for name, case in accepted.items()}))
    built = colcon(['build'], cwd=tmp_path / 'ws')
    assert built.returncode == 0, built.stdout + built.stderr
    install = tmp_path / 'ws' / 'install'
    values = _read_back(install, list(accepted), ros_env.free_domain_id())
    for name, (texts, array_items) in accepted.items():
        got = values[name]
        for i, text in enumerate(texts):
            assert got['fields'][f'f{i}'] == value_of(text), (name, texts)
            assert got['constants'][f'C{i}'] == value_of(text), (name, texts)
        assert got['fields']['items'] == [item_of(t) for t in array_items], (name, array_items)
        comments = _header_comments(install, name)
        # the struct's comment: the banner, then the description
        lines = _comment_lines(texts[0])
        assert comments['struct'][-len(lines):] == lines, (name, texts)
        assert comments['struct'][0].startswith('Generated by colcon-robmosys')
        for i, text in enumerate(texts):
            assert comments[f'f{i}'] == _comment_lines(text), (name, text)
            assert comments[f'C{i}'] == _comment_lines(text), (name, text)


@pytest.mark.parametrize('text, reason', [
    ('ends the comment */ int injected;', "holds '*/'"),
    ('a line that ends with \\\nint injected;', 'ends with a backslash'),
])
def test_what_would_become_c_is_refused_at_its_line(tmp_path, text, reason):
    model = tmp_path / 'robmosys.yaml'
    model.write_text(yaml.safe_dump(_model(['plain', 'plain'], ['a'])).replace(
        'comment: plain', 'comment: ' + json.dumps(text), 1))
    result = load_workspace([model])
    assert [(d.location.line > 0, reason in d.message) for d in result.errors] == [(True, True)]
