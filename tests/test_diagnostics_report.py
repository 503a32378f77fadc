# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""Reports of the real verbs on the corpus: the lines on stderr, each once, in a file.

The valid corpus (whose system leaves required ports unconnected: warnings)
with a broken case (three errors of three kinds), checked by
``colcon robmosys-generate`` and ``colcon build``; the JUnit reports are read
by the real ``colcon test-result``.
"""

from __future__ import annotations

import json
from pathlib import Path
import re
import shutil
import sys
import xml.etree.ElementTree as ElementTree

import pytest

from colcon_robmosys.devtools import ros_env
from conftest import requires_ros
from harness.fake_ament import fake_ament_index

pytestmark = [requires_ros, pytest.mark.integration]

MODELS = Path(__file__).parent / 'models'
BROKEN = MODELS / 'invalid' / 'multiple_errors_in_three_components.yaml'
_LINE = re.compile(r'^(/\S+?(?::\d+:\d+)?: (?:error|warning): .*)$', re.MULTILINE)


@pytest.fixture(scope='module')
def prefix(tmp_path_factory) -> Path:
    """Return the fake ament prefix the corpus is written against."""
    path = tmp_path_factory.mktemp('prefix')
    fake_ament_index(path)
    return path


def _workspace(root: Path, broken: bool) -> Path:
    cases = sorted((MODELS / 'valid').glob('*.yaml')) + ([BROKEN] if broken else [])
    for case in cases:
        folder = root / 'src' / case.stem
        folder.mkdir(parents=True)
        shutil.copyfile(case, folder / 'robmosys.yaml')
    return root


def _colcon(args: list[str], root: Path, prefix: Path):
    env = ros_env.loopback_env(ros_env.free_domain_id())
    env['AMENT_PREFIX_PATH'] = str(prefix)
    return ros_env.run([str(Path(sys.prefix) / 'bin' / 'colcon'), '--log-base',
                        str(root / 'log'), *args], env=env, cwd=root, timeout=300)


def _lines(stderr: str) -> list[str]:
    return _LINE.findall(stderr)


def _report_lines(fmt: str, path: Path) -> list[str]:
    """Return the compiler-style lines a report holds, read back from its format."""
    if fmt == 'json':
        return [d['text'] for d in json.loads(path.read_text())['diagnostics']]
    if fmt == 'sarif':
        (run,) = json.loads(path.read_text())['runs']
        lines = []
        for result in run['results']:
            physical = result['locations'][0]['physicalLocation']
            where = physical['artifactLocation']['uri'].removeprefix('file://')
            region = physical.get('region')
            if region:
                where += f":{region['startLine']}:{region['startColumn']}"
            lines.append(f"{where}: {result['level']}: {result['message']['text']}")
        return lines
    root = ElementTree.parse(path).getroot()
    lines = [f.text for f in root.iter('failure')]
    for stderr in root.iter('system-err'):
        lines += stderr.text.splitlines()
    return lines


@pytest.mark.parametrize('fmt', ['json', 'sarif', 'junit'])
def test_validate_only_reports_every_error_and_warning_once(tmp_path, prefix, fmt):
    root = _workspace(tmp_path, broken=True)
    # colcon test-result reads *.xml files only
    report = root / 'reports' / f"models.{'xml' if fmt == 'junit' else fmt}"
    result = _colcon(['robmosys-generate', '--validate-only', '--diagnostics-format', fmt,
                      '--diagnostics-file', str(report)], root, prefix)
    assert result.returncode == 1
    printed = _lines(result.stderr)
    assert len(printed) == len(set(printed)) == 8, result.stderr
    assert {line.split(': ')[1] for line in printed} == {'error', 'warning'}
    assert sorted(_report_lines(fmt, report)) == sorted(printed)
    if fmt == 'junit':
        # one test case per model file: the broken one fails, with its three errors
        out = _colcon(['test-result', '--test-result-base', str(report.parent), '--verbose'],
                      root, prefix)
        assert out.returncode != 0
        summary = out.stdout.splitlines()[-1]
        assert summary == f'Summary: {len(list((MODELS / "valid").glob("*.yaml"))) + 1} ' \
            'tests, 0 errors, 1 failure, 0 skipped', out.stdout
        assert all(line in out.stdout for line in printed if ': error: ' in line)


def test_generation_reports_its_warnings_and_a_clean_run_replaces_the_report(tmp_path, prefix):
    root = _workspace(tmp_path, broken=True)
    report = root / 'models.sarif'
    args = ['robmosys-generate', '--diagnostics-format', 'sarif', '--diagnostics-file',
            str(report), '--output-dir', str(root / 'generated')]
    assert _colcon(args, root, prefix).returncode == 1
    assert {r['level'] for r in json.loads(report.read_text())['runs'][0]['results']} == {
        'error', 'warning'}
    shutil.rmtree(root / 'src' / BROKEN.stem)
    result = _colcon(args, root, prefix)
    assert result.returncode == 0, result.stderr
    (run,) = json.loads(report.read_text())['runs']
    assert sorted(_report_lines('sarif', report)) == sorted(_lines(result.stderr))
    assert {r['level'] for r in run['results']} == {'warning'}
    assert len(run['results']) == 5


def test_a_file_of_the_user_is_not_replaced_by_a_report(tmp_path, prefix):
    root = _workspace(tmp_path, broken=False)
    mine = root / 'notes.json'
    mine.write_text('{"mine": true}\n')
    result = _colcon(['robmosys-generate', '--validate-only', '--diagnostics-format', 'json',
                      '--diagnostics-file', str(mine)], root, prefix)
    assert result.returncode == 1
    assert f'{mine}: error: the file exists and is no report of colcon-robmosys' in \
        result.stderr
    assert mine.read_text() == '{"mine": true}\n'


def test_build_writes_junit_where_colcon_test_result_finds_it(tmp_path, prefix):
    root = _workspace(tmp_path, broken=True)
    # (second_broken is a C++ component: skipped where rclcpp is missing)
    build = _colcon(['build', '--robmosys-test-results', '--continue-on-error',
                     '--packages-select', 'first_broken', 'third_broken'], root, prefix)
    assert build.returncode != 0
    errors = [line for line in _lines(build.stderr) if ': error: ' in line]
    assert len(errors) == 3
    # one file holds the three components: each package's model has its errors
    for package in ('first_broken', 'third_broken'):
        path = root / 'build' / package / 'test_results' / package / 'robmosys_model.xml'
        assert sorted(f.text for f in ElementTree.parse(path).getroot().iter('failure')) == \
            sorted(errors)
    out = _colcon(['test-result', '--verbose'], root, prefix)
    assert out.returncode != 0
    assert out.stdout.splitlines()[-1] == 'Summary: 2 tests, 0 errors, 2 failures, 0 skipped'
    # a build without the option removes the reports it would not renew
    _colcon(['build', '--continue-on-error', '--packages-select', 'first_broken'], root,
            prefix)
    assert not (root / 'build' / 'first_broken' / 'test_results' / 'first_broken' /
                'robmosys_model.xml').exists()
