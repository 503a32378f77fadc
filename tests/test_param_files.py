# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""Operators' parameter files checked against a system, offline.

``tests/params/robmosys.yaml`` is the system; each file of ``tests/params/invalid``
holds one defect and states the lines it must get, as the model corpus does::

    # expect: 3:11: error: parameter 'rate' of /robot1/driver: ...
    # options: --running

Each file of ``tests/params/valid`` gets no error (wildcards, nesting, rcl's own
spellings of values). The checker is robmosys_runtime.tools.paramcheck, the code of
``ros2 run <system> check_params`` and ``colcon robmosys-check params``; the
integration tests at the end run both as processes on the built test_workspace.
"""

from __future__ import annotations

import json
from pathlib import Path
import re
import shlex
import shutil
import sys
import xml.etree.ElementTree as ElementTree

import pytest

from colcon_robmosys.check import load_workspace
from colcon_robmosys.devtools.ros_env import free_domain_id, run
from colcon_robmosys.mapping.system import plan_system
from colcon_robmosys.runtime import runtime_module
from conftest import colcon, requires_ros, TEST_WORKSPACE
from harness.fake_ament import fake_ament_index

PARAMS = Path(__file__).parent / 'params'
INVALID = sorted((PARAMS / 'invalid').glob('*.yaml'))
VALID = sorted((PARAMS / 'valid').glob('*.yaml'))
_DIRECTIVE = re.compile(r'^# (expect|options): (.+)$', re.MULTILINE)

paramcheck = runtime_module('tools.paramcheck')


@pytest.fixture(scope='module')
def description(tmp_path_factory) -> dict:
    """Return the system's description, as its bringup.json holds it."""
    index = fake_ament_index(tmp_path_factory.mktemp('ament_prefix'))
    result = load_workspace([(PARAMS / 'robmosys.yaml').resolve()], index)
    assert result.errors == []
    return json.loads(plan_system(result.workspace.model('pf_system'),
                                  result.workspace).bringup_description)


def _check(description: dict, path: Path) -> tuple[set[str], set[str]]:
    """Return the lines a file gets (relative to its folder) and those it expects."""
    text = path.read_text(encoding='utf-8')
    expected, options = set(), []
    for kind, value in _DIRECTIVE.findall(text):
        if kind == 'options':
            options += shlex.split(value)
        else:
            expected.add(f'{path.name}:{value}')
    namespace = options[options.index('--namespace') + 1] if '--namespace' in options else ''
    found = paramcheck.check_files(description, [str(path)], namespace=namespace,
                                   running='--running' in options)
    got = {paramcheck.line(str(p), problem).replace(str(path.parent) + '/', '')
           for p, problem in found}
    return got, expected


def test_corpus_is_complete():
    assert len(INVALID) >= 20
    for path in INVALID:
        assert _DIRECTIVE.search(path.read_text()), f"{path.name} has no '# expect:' line"


@pytest.mark.parametrize('path', INVALID, ids=[p.stem for p in INVALID])
def test_invalid_parameter_file(path: Path, description: dict):
    got, expected = _check(description, path)
    assert got == expected


@pytest.mark.parametrize('path', VALID, ids=[p.stem for p in VALID])
def test_valid_parameter_file(path: Path, description: dict):
    got, expected = _check(description, path)
    assert got == expected
    assert not [g for g in got if ': error: ' in g]


@pytest.mark.parametrize('pattern, fqn, matches', [
    ('/**', '/a', True), ('/**', '/a/b/c', True),
    ('/robot1/*', '/robot1/driver', True), ('/robot1/*', '/robot1/arm/driver', False),
    ('/robot1/*', '/robot1', False), ('/robot1/**', '/robot1/arm/driver', True),
    ('/**/driver', '/driver', True), ('/**/driver', '/robot1/arm/driver', True),
    ('/*/driver', '/driver', False), ('/robot1/driver', '/robot1/driver', True),
    ('/robot1/driver', '/robot1/driver2', False),
])
def test_node_names_match_as_rclcpp_and_rclpy_match_them(pattern, fqn, matches):
    assert paramcheck.node_matches(pattern, fqn) is matches


def test_values_are_typed_as_rcl_types_them():
    read = runtime_module('tools.paramfile').read_text(
        '/a:\n  ros__parameters:\n    {}\n'.format('\n    '.join([
            'b: yes', 'i: 010', 'h: 0x1F', 'd: 08', 'e: 1e3', 'n: null', 'q: "5"',
            's: !!str 5', 'o: 1e999', 'x: .NaN', 'l: [Off, on]'])))
    assert read.problems == []
    values = {v.name: (v.kind, v.value) for v in read.entries[0].values}
    assert values.pop('x')[0] == 'double'
    assert values == {
        'b': ('bool', True), 'i': ('int', 8), 'h': ('int', 31), 'd': ('double', 8.0),
        'e': ('double', 1000.0), 'n': ('string', 'null'), 'q': ('string', '5'),
        's': ('string', '5'), 'o': ('string', '1e999'), 'l': ('bool[]', [False, True])}


def test_a_file_that_cannot_be_read_is_an_error_line(description, tmp_path):
    binary = tmp_path / 'binary.yaml'
    binary.write_bytes(b'\xff\xfe/a: 1\n')
    # the first byte that is not UTF-8, at its line and column (in characters)
    latin = tmp_path / 'latin.yaml'
    latin.write_bytes('/a:\n  ros__parameters:\n    städte: 1\n    frame: caf'.encode()
                      + b'\xe9\n')
    found = paramcheck.check_files(description, [str(tmp_path / 'missing.yaml'), str(binary),
                                                 str(latin)])
    assert [paramcheck.line(p, problem).replace(str(tmp_path), 'T') for p, problem in found] == [
        'T/missing.yaml: error: cannot read it: No such file or directory',
        'T/binary.yaml:1:1: error: not a text in UTF-8 (byte 0xff)',
        'T/latin.yaml:4:15: error: not a text in UTF-8 (byte 0xe9)']


BROKEN = """\
/**:
  ros__parameters:
    use_sim_time: true
/robot1/*:
  ros__parameters:
    noOfScans: three
robot2:
  publisher:
    ros__parameters:
      indor: true
"""
GOOD = """\
/**:
  ros__parameters:
    use_sim_time: true
/robot1/*:
  ros__parameters:
    noOfScans: 4
robot2:
  publisher:
    ros__parameters:
      indoor: false
"""


@pytest.mark.integration
@requires_ros
def test_installed_system_checks_a_file_with_ros2_run(test_workspace_built, tmp_path):
    """fleet_system as installed: its check_params executable, without colcon."""
    env = test_workspace_built.env(free_domain_id())
    (tmp_path / 'broken.yaml').write_text(BROKEN)
    (tmp_path / 'good.yaml').write_text(GOOD)
    executable = test_workspace_built.install / 'fleet_system' / 'lib' / 'fleet_system' / \
        'check_params'
    broken = run([sys.executable, str(executable), 'broken.yaml'], env=env, timeout=120,
                 cwd=tmp_path)
    assert broken.returncode == 1, broken.stdout + broken.stderr
    assert broken.stderr.splitlines() == [
        "broken.yaml:6:16: error: parameter 'noOfScans' of /robot1/publisher: 'three' is "
        'read as a string, the parameter is an int',
        "broken.yaml:10:7: error: node /robot2/publisher has no parameter 'indor'; did you "
        "mean 'indoor'? (its parameters: indoor, noOfScans, use_sim_time)"]
    good = run([sys.executable, str(executable), 'good.yaml'], env=env, timeout=120,
               cwd=tmp_path)
    assert (good.returncode, good.stderr) == (0, ''), good.stdout + good.stderr
    assert 'good.yaml: fits the system fleet_system' in good.stdout


@pytest.mark.integration
@requires_ros
@pytest.mark.parametrize('format_', ['json', 'sarif', 'junit'])
def test_colcon_verb_checks_an_installed_system_with_reports(
        test_workspace_built, tmp_path, format_):
    """Check with colcon robmosys-check params the installed fleet_system, each report format."""
    (tmp_path / 'broken.yaml').write_text(BROKEN)
    report = tmp_path / f'report.{format_}'
    result = colcon(['robmosys-check', 'params', 'broken.yaml', '--system', 'fleet_system',
                     '--diagnostics-format', format_, '--diagnostics-file', str(report)],
                    cwd=tmp_path, extra_env=test_workspace_built.env(free_domain_id()))
    assert result.returncode == 1, result.stdout + result.stderr
    assert 'broken.yaml:10:7: error: node /robot2/publisher' in result.stderr
    text = report.read_text()
    if format_ == 'json':
        assert [(d['line'], d['column']) for d in json.loads(text)['diagnostics']] == \
            [(6, 16), (10, 7)]
    elif format_ == 'sarif':
        results = json.loads(text)['runs'][0]['results']
        assert [r['locations'][0]['physicalLocation']['region']['startLine']
                for r in results] == [6, 10]
    else:
        case = ElementTree.fromstring(text).find('testsuite/testcase')
        assert case is not None and case.get('name') == 'broken.yaml'
        assert len(case.findall('failure')) == 2


@requires_ros
def test_colcon_verb_checks_a_system_of_the_workspace(tmp_path):
    """In the workspace, from the models: nothing built."""
    (tmp_path / 'good.yaml').write_text(GOOD)
    (tmp_path / 'broken.yaml').write_text(BROKEN)
    src = tmp_path / 'src'
    for package in ('simple_msgs', 'publisher', 'subscriber', 'pubsub_system', 'fleet_system'):
        shutil.copytree(TEST_WORKSPACE / 'src' / package, src / package)

    def check(file: str, system: str = 'fleet_system'):
        # --base-paths takes every argument after it
        return colcon(['robmosys-check', 'params', file, '--system', system,
                       '--base-paths', str(src)], cwd=tmp_path)

    good = check('good.yaml')
    assert good.returncode == 0, good.stdout + good.stderr
    broken = check('broken.yaml')
    assert broken.returncode == 1
    assert "broken.yaml:6:16: error: parameter 'noOfScans'" in broken.stderr
    unknown = check('good.yaml', 'no_system')
    assert unknown.returncode == 1
    assert unknown.stderr.startswith('no_system: error: no system of this name')
