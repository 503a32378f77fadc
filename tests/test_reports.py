# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""The report writers: JSON, SARIF 2.1.0 and JUnit XML read back, and the problem matcher.

SARIF is checked for the structure code scanning reads; where the SARIF 2.1.0
JSON Schema is at hand (``SARIF_SCHEMA=path/to/sarif-schema-2.1.0.json``, it
is not shipped here), it is validated against it too.
"""

from __future__ import annotations

import json
import os
from pathlib import Path
import re
import xml.etree.ElementTree as ElementTree

import pytest

from colcon_robmosys.check import load_workspace
from colcon_robmosys.errors import Diagnostic, Location
from colcon_robmosys.report import (
    MATCHER, report_problem, ReportRequest, TOOL, write_report)
from colcon_robmosys.report.formats import (
    json_report, junit_report, Report, sarif_report)
from harness.fake_ament import EXAMPLE_EXTRA, fake_ament_index

REPO = Path(__file__).resolve().parent.parent
MODELS = Path(__file__).parent / 'models'

ERROR = Diagnostic(Location('/ws/src/a/robmosys.yaml', 12, 5), "unknown port 'rMapp'")
WARNING = Diagnostic(Location('/ws/src/sys/robmosys.yaml', 17, 7),
                     "required port 'monitor.rGrid' is not connected", 'warning')
WHOLE_FILE = Diagnostic(Location('/ws/src/b/robmosys.yaml'), 'the file is empty')
HOSTILE = Diagnostic(Location('/ws/src/a/robmosys.yaml', 3, 1),
                     'a name holds \x01, "quotes", <tags> & ]]> \ud800')
CLEAN = '/ws/src/clean/robmosys.yaml'


def _report(*diagnostics: Diagnostic) -> Report:
    # each diagnostic given twice: every report holds it once
    return Report.of([CLEAN, ERROR.location.path], list(diagnostics) * 2)


def test_json_report_reads_back_every_diagnostic_once():
    document = json.loads(json_report(_report(ERROR, WARNING, WHOLE_FILE)))
    assert document['tool'] == TOOL
    assert (document['errors'], document['warnings']) == (2, 1)
    assert document['files'] == sorted({CLEAN, ERROR.location.path, WARNING.location.path,
                                        WHOLE_FILE.location.path})
    assert [(d['file'], d['line'], d['column'], d['severity'], d['message'], d['text'])
            for d in document['diagnostics']] == [
        (d.location.path, d.location.line, d.location.column, d.severity, d.message, str(d))
        for d in sorted([ERROR, WARNING, WHOLE_FILE])]


def _sarif(*diagnostics: Diagnostic) -> dict:
    return json.loads(sarif_report(_report(*diagnostics)))


def test_sarif_has_what_code_scanning_reads():
    document = _sarif(ERROR, WARNING, WHOLE_FILE)
    assert document['version'] == '2.1.0'
    (run,) = document['runs']
    driver = run['tool']['driver']
    assert driver['name'] == TOOL
    rules = [rule['id'] for rule in driver['rules']]
    results = run['results']
    assert len(results) == 3
    by_message = {r['message']['text']: r for r in results}
    error = by_message[ERROR.message]
    assert (error['ruleId'], error['level']) == ('model-error', 'error')
    assert rules[error['ruleIndex']] == error['ruleId']
    (location,) = error['locations']
    physical = location['physicalLocation']
    assert physical['artifactLocation']['uri'] == 'file:///ws/src/a/robmosys.yaml'
    assert physical['region'] == {'startLine': 12, 'startColumn': 5}
    warning = by_message[WARNING.message]
    assert (warning['ruleId'], warning['level']) == ('model-warning', 'warning')
    assert warning['locations'][0]['physicalLocation']['region'] == {
        'startLine': 17, 'startColumn': 7}
    # a problem of the whole file has no region
    whole = by_message[WHOLE_FILE.message]['locations'][0]['physicalLocation']
    assert 'region' not in whole
    assert {a['location']['uri'] for a in run['artifacts']} == {
        Path(p).as_uri() for p in (CLEAN, ERROR.location.path, WARNING.location.path,
                                   WHOLE_FILE.location.path)}


def test_sarif_uris_are_absolute_and_encoded(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    odd = Diagnostic(Location('src/a b/robmosys#1.yaml', 1, 1), 'm')
    (result,) = _sarif(odd)['runs'][0]['results']
    uri = result['locations'][0]['physicalLocation']['artifactLocation']['uri']
    assert uri == (tmp_path / 'src' / 'a b' / 'robmosys#1.yaml').as_uri()
    assert ' ' not in uri and '#' not in uri


@pytest.mark.skipif(not os.environ.get('SARIF_SCHEMA'),
                    reason='SARIF_SCHEMA names no copy of the SARIF 2.1.0 JSON Schema')
def test_sarif_is_valid_against_the_schema():
    from jsonschema import Draft4Validator, FormatChecker
    schema = json.loads(Path(os.environ['SARIF_SCHEMA']).read_text(encoding='utf-8'))
    validator = Draft4Validator(schema, format_checker=FormatChecker())
    for document in (_sarif(), _sarif(ERROR, WARNING, WHOLE_FILE, HOSTILE)):
        assert [e.message for e in validator.iter_errors(document)] == []


def test_junit_has_a_test_case_per_file_failed_by_its_errors():
    root = ElementTree.fromstring(junit_report(_report(ERROR, WARNING, WHOLE_FILE, HOSTILE)))
    assert root.tag == 'testsuites'
    (suite,) = root
    cases = {c.get('name'): c for c in suite.iter('testcase')}
    assert sorted(cases) == sorted({CLEAN, ERROR.location.path, WARNING.location.path,
                                    WHOLE_FILE.location.path})
    assert (suite.get('tests'), suite.get('failures'), suite.get('errors')) == ('4', '2', '0')
    failures = cases[ERROR.location.path].findall('failure')
    assert [f.text for f in failures] == [str(HOSTILE).replace('\x01', '\\x01').replace(
        '\ud800', '\\ud800'), str(ERROR)]
    assert cases[ERROR.location.path].get('line') == '3'
    assert cases[CLEAN].findall('failure') == []
    # warnings fail nothing: they are the file's stderr, as a compiler's are
    warned = cases[WARNING.location.path]
    assert warned.findall('failure') == []
    assert warned.find('system-err').text == f'{WARNING}\n'
    assert [f.get('message') for f in cases[WHOLE_FILE.location.path].findall('failure')] == [
        str(WHOLE_FILE)]


def test_junit_is_what_colcon_test_result_reads(tmp_path):
    xunit = pytest.importorskip('colcon_test_result.test_result.xunit')
    path = tmp_path / 'robmosys_model.xml'
    path.write_bytes(junit_report(_report(ERROR, WARNING)))
    result = xunit.parse_xunit_xml(str(path), get_testcases=True)
    assert (result.test_count, result.failure_count, result.error_count) == (3, 1, 0)
    assert any(str(ERROR) in detail for detail in result.details)


def test_a_report_replaces_a_report_only(tmp_path):
    path = tmp_path / 'out' / 'report.sarif'
    assert report_problem(path) is None
    write_report(ReportRequest('sarif', path), [CLEAN], [ERROR])
    first = path.read_bytes()
    assert report_problem(path) is None
    write_report(ReportRequest('sarif', path), [CLEAN], [])
    assert path.read_bytes() != first
    assert [p.name for p in path.parent.iterdir()] == ['report.sarif']
    mine = tmp_path / 'robmosys.yaml'
    mine.write_text('robmosys: 1\n')
    assert 'is no report of colcon-robmosys' in report_problem(mine)
    assert 'is a folder' in report_problem(tmp_path)


def test_default_file_names():
    assert ReportRequest.of(None, None) is None
    assert ReportRequest.of('junit', None).path == Path('robmosys-diagnostics.xml')
    assert ReportRequest.of('sarif', Path('x.json')).path == Path('x.json')


# the problem matcher of docs/ci.md ------------------------------------------

def _matchers() -> list[dict]:
    return json.loads(MATCHER.read_text(encoding='utf-8'))['problemMatcher']


def _match(line: str) -> list[dict[str, str]]:
    """Return what each matcher reads from a line, as GitHub's runner would."""
    found = []
    for matcher in _matchers():
        (pattern,) = matcher['pattern']
        match = re.search(pattern['regexp'], line)
        if match:
            found.append({key: match.group(index) for key, index in pattern.items()
                          if key != 'regexp'})
    return found


def _corpus_lines(tmp_path: Path) -> list[Diagnostic]:
    index = fake_ament_index(tmp_path / 'prefix', EXAMPLE_EXTRA)
    # a file that cannot be read: a problem of the whole file, without a line
    paths = sorted((MODELS / 'invalid').glob('*.yaml')) + sorted(
        (MODELS / 'valid').glob('*.yaml')) + [tmp_path / 'gone' / 'robmosys.yaml']
    return load_workspace(paths, index).diagnostics


def test_the_problem_matcher_reads_every_line_of_the_corpus(tmp_path):
    diagnostics = _corpus_lines(tmp_path)
    assert {d.severity for d in diagnostics} == {'error', 'warning'}
    assert any(not d.location.line for d in diagnostics)
    for diagnostic in diagnostics:
        (read,) = _match(str(diagnostic))
        assert read['file'] == diagnostic.location.path
        assert read['severity'] == diagnostic.severity
        assert read['message'] == diagnostic.message
        if diagnostic.location.line:
            assert (read['line'], read['column']) == (
                str(diagnostic.location.line), str(diagnostic.location.column))
    # colcon's own lines are no model diagnostics
    assert _match('Summary: 2 packages finished [1.2s]') == []
    assert _match('[0.3s] WARNING:colcon.colcon_core: something') == []


def test_docs_show_the_matcher_that_ships():
    text = (REPO / 'docs' / 'ci.md').read_text(encoding='utf-8')
    blocks = re.findall(r'```json\n(.*?)```', text, re.DOTALL)
    assert json.loads(MATCHER.read_text(encoding='utf-8')) in [json.loads(b) for b in blocks]
