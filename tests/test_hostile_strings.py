# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""Free text of a model reaches generated files only as data.

Every free-text slot of a model (descriptions, comments, string defaults and
constants, maintainer names, parameter strings of a system) is filled with a
hostile string, and the same model with a plain one. The generated files must
parse, have the very same structure in both cases (the hostile text changed
no code, markup or configuration), and give back the hostile text as data.
"""

from __future__ import annotations

import ast
import json
from pathlib import Path
import re
import shutil
import subprocess
import sys
import xml.etree.ElementTree as ET

import pytest
import yaml

from colcon_robmosys.check import find_model_files, load_workspace
from colcon_robmosys.check.index import InterfaceIndex
from colcon_robmosys.generators import (
    create_missing_user_files, generate_package, MANIFEST, read_manifest)
from colcon_robmosys.generators import plan_package
from colcon_robmosys.generators.filters import (
    cmake_str, cpp_str, LINE_LENGTH, py_literal, yaml_value)
from colcon_robmosys.model.fieldtypes import interface_comment_problem

PLAIN = 'Plain words'

HOSTILE = [
    '"); system("rm -rf /"); ("',
    "'); import os; os.system('id') #",
    '${HOME} $ENV{PATH} $<1:x> $(pwd) `id` @HOME@ %s {0}',
    '</description><evil attr="1"/><description>',
    "'''", '"""', '"""\'\'\'"', '\\', 'ends with a backslash \\', '\\n \\x00 \\u0041',
    '{{ 7 * 7 }} {% if x %} {# comment #}',
    'first line\nsecond line\n\n    indented line',
    'tab\there', 'carriage\r\nreturn\rsolo',
    'dashes -- in --> comments -', '# not a comment', '-->',
    'ünïcødé ✓ 日本語 😀 \u00a0nbsp \u2028separator \x85next',
    ': colon [flow, {map}] &anchor *alias !tag |',
    'null', 'yes', '0x10', ' leading and trailing ', '<![CDATA[ x ]]> &amp; & ;semi;colons;',
]


def msg_safe(text: str) -> bool:
    """Say whether a .msg file carries text as a string value rosidl_adapter reads as is.

    A backslash is carried too, spelled for the IDL step after the adapter's
    parse (test_rosidl_text reads it back from the built package).
    """
    return text.isprintable() and not set(text) & set('#=\\')


def _model_files(text: str) -> dict[str, dict]:
    """Return the model of each package, every free-text slot holding text."""
    # the .msg format has no escapes: the model refuses values it cannot
    # carry (test_model_invalid), so those get a plain value here
    value = text if msg_safe(text) else PLAIN
    # rosidl copies comments into C comments unescaped: the model refuses
    # what would end one (test_rosidl_text)
    comment = PLAIN if interface_comment_problem(text) else text
    who = {'license': 'Apache-2.0', 'maintainers': [{'name': text, 'email': 'a@example.com'}]}
    return {
        'hostile_msgs': {'robmosys': 1, 'service_definitions': [{
            'package': 'hostile_msgs', 'description': text, **who,
            'communication_objects': {'Note': {
                'description': comment,
                'constants': {'GREETING': {'type': 'string', 'value': value,
                                           'comment': comment}},
                'fields': {'text': {'type': 'string', 'default': value, 'comment': comment},
                           'count': {'type': 'int32', 'comment': comment}},
            }},
        }]},
        'hostile': {'robmosys': 1, 'components': [{
            'name': 'Hostile', 'package': 'hostile', 'language': 'python',
            'description': text, **who,
            'ports': {
                'pNote': {'pattern': 'push', 'role': 'provided',
                          'type': 'hostile_msgs/msg/Note', 'description': text},
                'rNote': {'pattern': 'push', 'role': 'required',
                          'type': 'hostile_msgs/msg/Note', 'description': text},
            },
            'activities': {
                'Loop': {'period': 1.0, 'functions': ['fCoded'], 'description': text},
                'OnNote': {'trigger': 'rNote', 'functions': ['fUser'],
                           'description': text},
            },
            'functions': {
                'fCoded': {'description': text, 'code': 'self.count = 1\n'},
                'fUser': {'description': text},
            },
            'parameters': {
                'label': {'type': 'string', 'default': text, 'description': text},
                'labels': {'type': 'string[]', 'default': [text, text]},
                'gain': {'type': 'double', 'default': 0.5, 'description': text},
            },
        }]},
        'hostile_cpp': {'robmosys': 1, 'components': [{
            'name': 'HostileCpp', 'package': 'hostile_cpp', 'language': 'cpp',
            'description': text, **who,
            'ports': {
                'pNote': {'pattern': 'push', 'role': 'provided',
                          'type': 'hostile_msgs/msg/Note', 'description': text},
                'rNote': {'pattern': 'push', 'role': 'required',
                          'type': 'hostile_msgs/msg/Note', 'description': text},
            },
            'activities': {
                'Loop': {'period': 1.0, 'functions': ['fCoded'], 'description': text},
                'OnNote': {'trigger': 'rNote', 'functions': ['fUser'],
                           'description': text},
            },
            'functions': {
                'fCoded': {'description': text, 'code': 'count_ = 1;\n'},
                'fUser': {'description': text},
            },
            'parameters': {
                'label': {'type': 'string', 'default': text, 'description': text},
                'labels': {'type': 'string[]', 'default': [text, text]},
                'gain': {'type': 'double', 'default': 0.5, 'description': text},
            },
        }]},
        'hostile_system': {'robmosys': 1, 'systems': [{
            'package': 'hostile_system', 'description': text, **who,
            'instances': {'node': {'component': 'hostile',
                                   'parameters': {'label': text, 'labels': [text]}}},
        }]},
    }


def _generate(root: Path, text: str) -> Path:
    """Write the models of text under root/src, generate into root/out."""
    src, out = root / 'src', root / 'out'
    for package, model in _model_files(text).items():
        (src / package).mkdir(parents=True)
        (src / package / 'robmosys.yaml').write_text(
            yaml.safe_dump(model, allow_unicode=True, sort_keys=False), encoding='utf-8')
    result = load_workspace(find_model_files([src]), InterfaceIndex([Path(sys.prefix)]))
    result.raise_errors()
    for model in result.workspace.generated_models:
        plan = plan_package(result.workspace, model.package)
        create_missing_user_files(plan)
        generate_package(plan, out / model.package)
    return out


def _is_python(path: Path) -> bool:
    return path.suffix == '.py' or path.read_bytes().startswith(b'#!/usr/bin/env python')


def _python_shape(text: str) -> tuple[str, list[str]]:
    """Return the code of a Python file with its strings blanked, and its strings."""
    tree = ast.parse(text)
    strings = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Constant) and isinstance(node.value, str):
            strings.append(node.value)
            node.value = ''
    return ast.dump(tree), strings


_CPP_TOKEN = re.compile(r"""
    (?P<comment>//[^\n]*|/\*.*?\*/)
  | (?P<string>"(?:\\.|[^"\\\n])*")
  | (?P<char>'(?:\\.|[^'\\\n])*')
  | (?P<space>\s+)
  | (?P<other>\w+|.)
""", re.S | re.X)

_CPP_ESCAPE = re.compile(r'\\([0-7]{1,3}|.)', re.S)


def _cpp_decode(body: str) -> str:
    """Return the text of the inside of a C++ string literal."""
    out, pos = bytearray(), 0
    for match in _CPP_ESCAPE.finditer(body):
        out += body[pos:match.start()].encode('utf-8')
        escape = match.group(1)
        if escape[0] in '01234567':
            out.append(int(escape, 8))
        else:
            out += {'n': b'\n', 't': b'\t', 'r': b'\r'}.get(escape, escape.encode('utf-8'))
        pos = match.end()
    out += body[pos:].encode('utf-8')
    return out.decode('utf-8')


def _cpp_shape(text: str) -> tuple[list[str], list[str], list[str]]:
    """Return the tokens of C++ code without strings and comments, and those.

    Adjacent string literals, which the compiler joins, are one string.
    """
    shape: list[str] = []
    strings: list[str] = []
    comments: list[str] = []
    for match in _CPP_TOKEN.finditer(text):
        kind, token = match.lastgroup, match.group()
        if kind == 'comment':
            comments.append(token)
        elif kind == 'string':
            if shape and shape[-1] == '""':
                strings[-1] += _cpp_decode(token[1:-1])
            else:
                shape.append('""')
                strings.append(_cpp_decode(token[1:-1]))
        elif kind != 'space':
            shape.append(token)
    return shape, strings, comments


def _xml_shape(element: ET.Element) -> tuple:
    return (element.tag, sorted(element.attrib),
            [_xml_shape(child) for child in element])


def _yaml_shape(value: object) -> object:
    if isinstance(value, dict):
        return {k: _yaml_shape(v) for k, v in value.items()}
    if isinstance(value, list):
        return [_yaml_shape(v) for v in value]
    return type(value).__name__


def _words(text: str) -> str:
    return ' '.join(text.split())


@pytest.fixture(scope='module')
def plain(tmp_path_factory) -> Path:
    return _generate(tmp_path_factory.mktemp('plain'), PLAIN)


def _files(root: Path) -> dict[str, Path]:
    return {str(p.relative_to(root)): p for p in sorted(root.rglob('*')) if p.is_file()}


@pytest.mark.parametrize('text', HOSTILE, ids=[f'hostile{i}' for i in range(len(HOSTILE))])
def test_hostile_text_is_only_data(tmp_path, plain, text):
    from catkin_pkg.package import parse_package_string
    from rosidl_adapter.parser import parse_message_string

    out = _generate(tmp_path, text)
    files, plain_files = _files(out), _files(plain)
    assert files.keys() == plain_files.keys()
    seen = set()
    for name, path in files.items():
        data = path.read_text(encoding='utf-8')
        plain_data = plain_files[name].read_text(encoding='utf-8')
        if _is_python(path):
            shape, strings = _python_shape(data)
            assert shape == _python_shape(plain_data)[0], f'{name}: the code changed'
            if text in strings:
                seen.add('python')
            if any(_words(text) in _words(s) for s in strings):
                seen.add('docstring')
        elif path.name == 'package.xml':
            root = ET.fromstring(data.encode('utf-8'))
            assert _xml_shape(root) == _xml_shape(ET.fromstring(plain_data.encode('utf-8')))
            assert root.findtext('description') == text.strip()  # the model strips it
            assert [m.text for m in root.iter('maintainer')] == [text]
            assert [m.get('email') for m in root.iter('maintainer')] == ['a@example.com']
            parse_package_string(data)  # what ament_cmake reads
            seen.add('xml')
        elif path.parent.name == 'robmosys' and path.suffix == '.yaml':
            # the installed copy of the package's model reads as the model itself
            package = path.relative_to(out).parts[0]
            source = tmp_path / 'src' / package / 'robmosys.yaml'
            assert yaml.safe_load(data) == yaml.safe_load(source.read_text(encoding='utf-8'))
            seen.add('installed model')
        elif path.suffix == '.yaml':
            params = yaml.safe_load(data)
            assert _yaml_shape(params) == _yaml_shape(yaml.safe_load(plain_data))
            assert params['/node']['ros__parameters'] == {'label': text, 'labels': [text]}
            seen.add('yaml')
        elif path.suffix == '.msg':
            spec = parse_message_string('hostile_msgs', path.stem, data)
            plain_spec = parse_message_string('hostile_msgs', path.stem, plain_data)
            assert [(str(f.type), f.name) for f in spec.fields] == \
                [(str(f.type), f.name) for f in plain_spec.fields]
            assert [(c.type, c.name) for c in spec.constants] == \
                [(c.type, c.name) for c in plain_spec.constants]
            value = text if msg_safe(text) else PLAIN
            assert spec.fields[0].default_value == value
            assert spec.constants[0].value == value
            seen.add('msg')
        elif path.suffix in ('.cpp', '.hpp'):
            shape, strings, comments = _cpp_shape(data)
            assert shape == _cpp_shape(plain_data)[0], f'{name}: the code changed'
            if text in strings:
                seen.add('cpp')
            # a text of several lines is a run of // comments
            if _words(text) in _words(' '.join(c.lstrip('/') for c in comments)):
                seen.add('cpp comment')
        elif path.suffix == '.md':
            # the parameter page: each cell reads back as the text, none ends early
            rows, plain_rows = _md_rows(data), _md_rows(plain_data)
            assert [len(r) for r in rows] == [len(r) for r in plain_rows]
            label = next(r for r in rows if r[0] == '`label`')
            assert label[2] == repr(text)
            assert label[-1] == '\n'.join(line.strip() for line in text.strip().splitlines())
            # no tag but the line breaks: every other '<' of the text is escaped
            table = [re.sub(r'\\.|<br>', '', line) for line in data.splitlines()
                     if line.startswith('| ')]
            assert not any('<' in line for line in table)
            seen.add('markdown')
        elif path.suffix == '.json':
            # the system manager's description: JSON whatever the text, which reads back
            # as the value the model gives, and changes nothing else
            def values(description: dict) -> list:
                return [p['value'] for i in description['instances']
                        for p in i.get('parameters', [])]
            description, plain = json.loads(data), json.loads(plain_data)
            assert text in values(description) and text not in values(plain)
            assert json.dumps(description).replace(json.dumps(text), '""') == \
                json.dumps(plain).replace(json.dumps(PLAIN), '""')
            seen.add('json')
        elif path.name == MANIFEST:
            assert read_manifest(path).keys() == read_manifest(plain_files[name]).keys()
        else:
            # CMakeLists.txt, diagrams: no free text goes there
            # (a generator that starts writing some must check it parses here)
            assert data == plain_data, f'{name}: model text reached a file not checked here'
    assert seen == {'python', 'docstring', 'xml', 'yaml', 'msg', 'cpp', 'cpp comment',
                    'installed model', 'markdown', 'json'}


def _md_rows(page: str) -> list[list[str]]:
    """Return the cells of the rows of a Markdown table, unescaped, as CommonMark reads them."""
    rows = []
    for line in page.splitlines():
        if not line.startswith('| ') or line.startswith('| ---'):
            continue
        cells, cell, i = [], '', 1
        while i < len(line):
            if line[i] == '\\':
                cell, i = cell + line[i + 1], i + 2
            elif line.startswith('<br>', i):
                cell, i = cell + '\n', i + 4
            elif line[i] == '|':
                cells.append(cell.strip())
                cell, i = '', i + 1
            else:
                cell, i = cell + line[i], i + 1
        rows.append(cells)
    return rows


def test_no_control_character_reaches_a_model(tmp_path):
    path = tmp_path / 'robmosys.yaml'
    path.write_text('robmosys: 1\nservice_definitions:\n  - package: ctl_msgs\n'
                    '    description: "bell \\a and nul \\0"\n')
    result = load_workspace([path], InterfaceIndex([Path(sys.prefix)]))
    assert [str(e) for e in result.errors] == [
        f'{path}:4:18: error: the string holds the character U+0007, which a model may '
        'not hold: only printable characters, tabs and line breaks can reach the '
        'generated files']


@pytest.mark.parametrize('value', [*HOSTILE, ['a', '"b"'], 2.0, -3, True, 'ä\x7f\x9f\ufeff'])
def test_yaml_value_reads_back(value):
    assert yaml.safe_load(f'key: {yaml_value(value)}\n') == {'key': value}


@pytest.mark.parametrize('value', [
    *HOSTILE,
    ('aFibonacci/_action/cancel_goal',
     '/examples/fibonacci_server/aFibonacci/_action/cancel_goal'),
    ['x' * 120, ('short', 'y' * 200)],
])
def test_py_literal_reads_back_and_fits(value):
    """A literal written at the deepest indent of the launch files keeps ament_flake8's limit."""
    text = py_literal(value, 16)
    assert ast.literal_eval(text) == value
    lines = (' ' * 16 + text + ',').splitlines()
    assert all(len(line) <= LINE_LENGTH for line in lines), text


def test_cmake_strings_are_data(tmp_path):
    """Real cmake reads each quoted argument back as the text itself."""
    cmake = shutil.which('cmake') or shutil.which('cmake', path=str(Path(sys.prefix) / 'bin'))
    if cmake is None:
        pytest.skip('cmake is not installed')
    script = tmp_path / 'strings.cmake'
    lines = [f'file(WRITE "{tmp_path}/{i}.txt" {cmake_str(text)})' for i, text in
             enumerate(HOSTILE)]
    script.write_text('\n'.join(lines) + '\n', encoding='utf-8')
    subprocess.run([cmake, '-P', str(script)], check=True, timeout=60, capture_output=True)
    for i, text in enumerate(HOSTILE):
        assert (tmp_path / f'{i}.txt').read_bytes() == text.encode('utf-8'), text


def test_cpp_strings_are_data(tmp_path):
    """A real C++ compiler reads each string literal back as the text itself."""
    compiler = shutil.which('g++') or shutil.which('c++')
    if compiler is None:
        pytest.skip('no C++ compiler')
    texts = [*HOSTILE, '??=trigraph??/', '\x01\x7f octal 7\x017', 'nul\x00inside']
    source = tmp_path / 'strings.cpp'
    literals = ',\n'.join(f'std::string({cpp_str(t)}, {len(t.encode())})' for t in texts)
    source.write_text(
        '#include <iostream>\n#include <string>\n#include <vector>\n'
        f'int main() {{\n  std::vector<std::string> texts = {{\n{literals}}};\n'
        '  for (const auto & t : texts) {std::cout << t.size() << ":" << t;}\n}\n')
    binary = tmp_path / 'strings'
    subprocess.run([compiler, '-std=c++17', '-Wall', '-Werror', '-o', str(binary),
                    str(source)], check=True, timeout=120, capture_output=True)
    output = subprocess.run([str(binary)], check=True, timeout=30,
                            capture_output=True).stdout
    assert output == b''.join(b'%d:%s' % (len(t.encode()), t.encode()) for t in texts)
