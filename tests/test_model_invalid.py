# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""Every invalid model yields exactly the diagnostics its file announces.

Each file of ``tests/models/invalid`` holds one defect and states what must be
reported in leading comments::

    # expect: 14:13: error: unknown function 'fMissing' (known: fPublishing)
    # with: ../valid/component_python.yaml

An ``expect`` line without a file name is about the file itself; one with a
file name (relative to the invalid file) is about another file it loads.
``with`` names further model files loaded into the same workspace. Paths in
messages are written relative to the invalid file, so the expectations do not
depend on where the repository lies.
"""

from __future__ import annotations

import os
from pathlib import Path
import re

import pytest

from colcon_robmosys.check import load_workspace
from colcon_robmosys.check.index import InterfaceIndex
from harness.fake_ament import fake_ament_index

MODELS = Path(__file__).parent / 'models'
INVALID = sorted((MODELS / 'invalid').glob('*.yaml'))

_DIRECTIVE = re.compile(r'^# (expect|with): (.+)$', re.MULTILINE)


@pytest.fixture(scope='module')
def index(tmp_path_factory) -> InterfaceIndex:
    """Return an index of a fake ament prefix, so that no ROS is needed."""
    return fake_ament_index(tmp_path_factory.mktemp('ament_prefix'))


def _directives(path: Path) -> tuple[set[str], list[Path]]:
    """Return the expected diagnostics and the other files to load."""
    # read as bytes: a test file may hold bytes that are not UTF-8
    text = path.read_bytes().decode('utf-8', errors='replace')
    expected, others = set(), []
    for kind, value in _DIRECTIVE.findall(text):
        if kind == 'with':
            others.append((path.parent / value).resolve())
        elif value[0].isdigit():
            expected.add(f'{path.name}:{value}')
        else:
            expected.add(value)
    return expected, others


def test_corpus_is_complete():
    assert len(INVALID) >= 40
    for path in INVALID:
        expected, _ = _directives(path)
        assert expected, f"{path.name} has no '# expect:' line"


@pytest.mark.parametrize('path', INVALID, ids=[p.stem for p in INVALID])
def test_invalid_model(path: Path, index: InterfaceIndex):
    expected, others = _directives(path)
    paths = [path.resolve(), *others]
    result = load_workspace(paths, index)

    def relative(text: str) -> str:
        for loaded in paths:
            text = text.replace(
                str(loaded), os.path.relpath(loaded, path.parent))
        return text

    assert {relative(str(d)) for d in result.errors} == expected
