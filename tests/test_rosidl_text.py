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


def _model(texts: list[str], array_items: list[str]) -> dict:
    fields = {f'f{i}': {'type': 'string', 'default': value_of(text), 'comment': text}
              for i, text in enumerate(texts)}
    fields['items'] = {'type': 'string[]', 'default': [item_of(t) for t in array_items]}
    constants = {f'C{i}': {'type': 'string', 'value': value_of(text), 'comment': text}
                 for i, text in enumerate(texts)}
    return {'robmosys': 1, 'service_definitions': [{
        'package': PACKAGE, 'license': 'Apache-2.0',
        'maintainers': [{'name': 'A', 'email': 'a@example.com'}],
        'communication_objects': {MESSAGE: {
            'description': texts[0], 'fields': fields, 'constants': constants}}}]}


def _refusal_holds(message: str, texts: list[str]) -> bool:
    """Say whether a refusal names a reason that one of the texts really has."""
    return 'C comment' in message and any(interface_comment_problem(t) for t in texts)


def _read_back(install: Path, domain_id: int) -> dict:
    """Return the defaults and constants of the built Python message."""
    code = (f'import json\nfrom {PACKAGE}.msg import {MESSAGE} as M\n'
            'm = M()\n'
            'fields = {n: getattr(m, n) for n in m.get_fields_and_field_types()}\n'
            'constants = {n: getattr(m, n) for n in dir(M) if n[1:].isdigit()}\n'
            'print(json.dumps({"fields": fields, "constants": constants}))')
    env = ros_env.workspace_env(install, ros_env.loopback_env(domain_id))
    result = ros_env.run([sys.executable, '-c', code], env=env, timeout=60)
    assert result.returncode == 0, result.stderr
    return json.loads(result.stdout.splitlines()[-1])


def _header_comments(install: Path) -> dict[str, list[str]]:
    """Return the comment of the struct, of each constant and of each member.

    rosidl_generator_c writes them into the message's C header: the struct's
    and the constants' inside ``/** */``, the members' after ``///``.
    """
    header = (install / PACKAGE / 'include' / PACKAGE / PACKAGE / 'msg' / 'detail' /
              f'{MESSAGE.lower()}__struct.h').read_text(encoding='utf-8')
    comments = {}
    for block, name in re.findall(
            r'/\*\*\n((?:  \*.*\n)*) \*/\n(?:static const .*__(C\d+) =|typedef struct)',
            header):
        comments[name or 'struct'] = [re.sub(r'^  \* ?', '', line)
                                      for line in block.splitlines()]
    for block, name in re.findall(r'((?:  ///.*\n)*)  \S.* (\w+);\n', header):
        comments[name] = [re.sub(r'^  /// ?', '', line) for line in block.splitlines()]
    return comments


@settings(max_examples=8, deadline=None, derandomize=True,
          suppress_health_check=[HealthCheck.function_scoped_fixture,
                                 HealthCheck.too_slow])
@given(texts=st.lists(TEXT, min_size=2, max_size=6),
       array_items=st.lists(TEXT, min_size=1, max_size=3))
# the hard cases, whatever hypothesis draws: each escaping and non-ASCII
@example(texts=['back\\slash and "quotes" /* ??/ end\nsecond line', 'grüß 日本 😀 \\ x'],
         array_items=['plain', 'words'])
def test_text_reads_back_from_the_built_package(tmp_path_factory, texts, array_items):
    root = tmp_path_factory.mktemp('rosidl_text')
    model = root / 'src' / PACKAGE / 'robmosys.yaml'
    model.parent.mkdir(parents=True)
    model.write_text(yaml.safe_dump(_model(texts, array_items), allow_unicode=True),
                     encoding='utf-8')
    result = load_workspace([model])
    errors = [d for d in result.errors if d.location.path == str(model)]
    if errors:
        # refused: at the model's line, for a reason the text has
        for error in errors:
            assert error.location.line > 0, error
            assert _refusal_holds(error.message, texts), error
        # and what the check refuses, the build refuses with the same lines
        built = colcon(['build'], cwd=root)
        assert built.returncode != 0
        for error in errors:
            assert str(error) in built.stderr
        return
    built = colcon(['build'], cwd=root)
    assert built.returncode == 0, built.stdout + built.stderr
    install = root / 'install'
    values = _read_back(install, ros_env.free_domain_id())
    for i, text in enumerate(texts):
        assert values['fields'][f'f{i}'] == value_of(text)
        assert values['constants'][f'C{i}'] == value_of(text)
    assert values['fields']['items'] == [item_of(t) for t in array_items]
    comments = _header_comments(install)
    # the struct's comment: the banner, then the description
    assert comments['struct'][-len(_comment_lines(texts[0])):] == _comment_lines(texts[0])
    assert comments['struct'][0].startswith('Generated by colcon-robmosys')
    for i, text in enumerate(texts):
        assert comments[f'f{i}'] == _comment_lines(text)
        assert comments[f'C{i}'] == _comment_lines(text)
    shutil.rmtree(root)


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
