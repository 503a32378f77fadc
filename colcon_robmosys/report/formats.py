# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

"""The writers of the report formats: JSON, SARIF 2.1.0, JUnit XML."""

from __future__ import annotations

from dataclasses import dataclass
import json
import os
from pathlib import Path
import re
from typing import Any, Iterable
import xml.etree.ElementTree as ElementTree

from colcon_robmosys.errors import Diagnostic

#: the tool's name in every report; also what tells a report of ours
TOOL = 'colcon-robmosys'
#: the host of the model format's schema ($id of robmosys-1.schema.json)
TOOL_URI = 'https://colcon-robmosys.org'
#: the version of our own JSON format
JSON_VERSION = 1
SARIF_SCHEMA = 'https://json.schemastore.org/sarif-2.1.0.json'
#: SARIF rule of each severity: diagnostics carry no rule of their own
RULES = {
    'error': ('model-error', 'A model breaks a rule of the format: nothing is '
              'generated from its file, and the build fails.'),
    'warning': ('model-warning', 'A model is valid but probably not what was '
                'meant (a required port left unconnected): the build goes on.'),
}
#: what XML 1.0 cannot hold, even escaped
_NOT_XML = re.compile('[^\t\n\r\x20-\ud7ff\ue000-\ufffd\U00010000-\U0010ffff]')


@dataclass(frozen=True)
class Report:
    """The model files a run checked and what it found in them."""

    #: every file checked, and every file a diagnostic is about
    files: tuple[str, ...]
    #: each once, sorted by file, line and column
    diagnostics: tuple[Diagnostic, ...]

    @classmethod
    def of(cls, files: Iterable[str], diagnostics: Iterable[Diagnostic]) -> 'Report':
        """Return the report of files and diagnostics, each once."""
        found = tuple(sorted(set(diagnostics)))
        return cls(tuple(sorted(set(files) | {d.location.path for d in found})), found)

    def of_file(self, path: str) -> list[Diagnostic]:
        """Return the diagnostics located in one file."""
        return [d for d in self.diagnostics if d.location.path == path]

    def count(self, severity: str) -> int:
        """Return how many diagnostics have a severity."""
        return sum(d.severity == severity for d in self.diagnostics)


def _version() -> str:
    from colcon_robmosys import __version__
    return __version__


def json_report(report: Report) -> bytes:
    """Write the report in the JSON format of docs/ci.md."""
    document = {
        'tool': TOOL,
        'tool_version': _version(),
        'format_version': JSON_VERSION,
        'files': list(report.files),
        'errors': report.count('error'),
        'warnings': report.count('warning'),
        'diagnostics': [{
            'file': d.location.path, 'line': d.location.line, 'column': d.location.column,
            'severity': d.severity, 'message': d.message, 'text': str(d),
        } for d in report.diagnostics],
    }
    return (json.dumps(document, indent=2) + '\n').encode('utf-8')


def file_uri(path: str) -> str:
    """Return the absolute ``file:`` URI of a path (relative: to the current folder)."""
    return Path(os.path.abspath(path)).as_uri()


def _sarif_result(diagnostic: Diagnostic) -> dict[str, Any]:
    location = diagnostic.location
    physical: dict[str, Any] = {'artifactLocation': {'uri': file_uri(location.path)}}
    if location.line:
        physical['region'] = {'startLine': location.line}
        if location.column:
            physical['region']['startColumn'] = location.column
    rule_id, _ = RULES[diagnostic.severity]
    return {
        'ruleId': rule_id,
        'ruleIndex': list(RULES).index(diagnostic.severity),
        'level': diagnostic.severity,
        'message': {'text': diagnostic.message},
        'locations': [{'physicalLocation': physical}],
    }


def sarif_report(report: Report) -> bytes:
    """Write the report as a SARIF 2.1.0 log of one run.

    Locations are absolute ``file:`` URIs: github/codeql-action/upload-sarif
    makes them relative to its ``checkout_path``, wherever in the checkout
    the colcon workspace lies.
    """
    rules = [{
        'id': rule_id, 'name': rule_id.replace('-', ' ').title().replace(' ', ''),
        'shortDescription': {'text': description},
        'defaultConfiguration': {'level': severity},
    } for severity, (rule_id, description) in RULES.items()]
    document = {
        '$schema': SARIF_SCHEMA,
        'version': '2.1.0',
        'runs': [{
            'tool': {'driver': {
                'name': TOOL, 'version': _version(), 'informationUri': TOOL_URI,
                'rules': rules}},
            'artifacts': [{'location': {'uri': file_uri(path)}} for path in report.files],
            'results': [_sarif_result(d) for d in report.diagnostics],
            'columnKind': 'unicodeCodePoints',
        }],
    }
    return (json.dumps(document, indent=2) + '\n').encode('utf-8')


def _xml_text(text: str) -> str:
    """Return text that XML 1.0 can hold: what it cannot is written as an escape."""
    return _NOT_XML.sub(lambda m: ascii(m.group())[1:-1], text)


def junit_report(report: Report) -> bytes:
    """Write the report as JUnit XML: one test case per model file.

    A file with errors is a failed test case, one ``failure`` per error; its
    warnings are its ``system-err``, as a compiler's warnings are (they fail
    nothing). ``colcon test-result`` reads it like the results of a test.
    """
    failed = sum(bool([d for d in report.of_file(p) if d.severity == 'error'])
                 for p in report.files)
    counts = {'tests': str(len(report.files)), 'failures': str(failed),
              'errors': '0', 'skipped': '0'}
    root = ElementTree.Element('testsuites', {'name': TOOL, **counts})
    suite = ElementTree.SubElement(root, 'testsuite', {'name': 'robmosys.models', **counts})
    for path in report.files:
        found = report.of_file(path)
        errors = [d for d in found if d.severity == 'error']
        case = ElementTree.SubElement(suite, 'testcase', {
            'classname': 'robmosys.models', 'name': _xml_text(path), 'file': _xml_text(path),
            'time': '0'})
        if errors and errors[0].location.line:
            case.set('line', str(errors[0].location.line))
        for error in errors:
            failure = ElementTree.SubElement(
                case, 'failure', {'message': _xml_text(str(error)), 'type': 'error'})
            failure.text = _xml_text(str(error))
        warnings = [str(d) for d in found if d.severity != 'error']
        if warnings:
            ElementTree.SubElement(case, 'system-err').text = _xml_text(
                '\n'.join(warnings) + '\n')
    ElementTree.indent(root)
    data: bytes = ElementTree.tostring(root, encoding='utf-8', xml_declaration=True)
    return data + b'\n'
