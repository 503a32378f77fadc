# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""What colcon prints of models, and what a run with no change leaves alone.

Each model error is one bare ``path:line:col: error: message`` line on stderr,
printed once however many packages its file declares, so that editors and CI
problem matchers (GCC format) pick it up; colcon's own summary stays.
"""

from __future__ import annotations

from pathlib import Path
import re
import shutil

import pytest

from conftest import colcon, requires_ros, TEST_WORKSPACE

pytestmark = [requires_ros, pytest.mark.integration]

SEND_EXAMPLE = Path('src') / 'send_example' / 'robmosys.yaml'


@pytest.fixture
def workspace(tmp_path) -> Path:
    """Return a fresh copy of test_workspace (sources only)."""
    shutil.copytree(TEST_WORKSPACE / 'src', tmp_path / 'src',
                    ignore=shutil.ignore_patterns('__pycache__'))
    return tmp_path


def _break_both_components(workspace: Path) -> tuple[Path, list[str]]:
    """Put one error into each of the two components of send_example."""
    model = workspace / SEND_EXAMPLE
    text = model.read_text()
    text = text.replace('functions: [fSend]', 'functions: [fSendd]')
    text = text.replace('trigger: sText', 'trigger: sTextt')
    model.write_text(text)
    return model, [
        f"{model}:22:21: error: unknown function 'fSendd' (known: fReset, fSend, "
        'fStyleChanged, vGreeting)',
        f"{model}:86:18: error: activity 'Receive' is triggered by unknown port "
        "'sTextt' (known: sText)",
    ]


def _diagnostic_lines(stderr: str) -> list[str]:
    return [line for line in stderr.splitlines() if re.search(r': (error|warning): ', line)]


@pytest.mark.parametrize('verb', [
    ['build', '--packages-select', 'sender', 'receiver'],
    ['robmosys-generate', '--validate-only'],
])
def test_each_error_is_one_bare_line_once(workspace, verb):
    model, expected = _break_both_components(workspace)
    result = colcon(verb, cwd=workspace)
    lines = _diagnostic_lines(result.stderr)
    # exactly the model's errors, each once, each the whole line: nothing
    # before the path (no logger prefix), so a GCC problem matcher reads it
    assert sorted(lines) == sorted(expected), result.stderr
    assert str(model) not in result.stdout
    assert result.returncode != 0
    if verb[0] == 'build':
        # colcon's summary still says which packages failed
        assert re.search(r'2 packages failed: receiver sender', result.stdout), result.stdout


def test_the_actual_messages_are_what_the_check_says(workspace):
    """The expected lines above are the check stage's own, not a guess."""
    from colcon_robmosys.check import find_model_files, load_workspace
    model, expected = _break_both_components(workspace)
    result = load_workspace(find_model_files([workspace / 'src']))
    assert sorted(str(d) for d in result.errors if d.location.path == str(model)) == \
        sorted(expected)


def test_a_regeneration_with_no_change_touches_nothing(workspace):
    first = colcon(['robmosys-generate', '--output-dir', 'gen'], cwd=workspace)
    assert first.returncode == 0, first.stderr
    stamps = {p: p.stat().st_mtime_ns for p in workspace.rglob('*')}
    second = colcon(['robmosys-generate', '--output-dir', 'gen'], cwd=workspace)
    assert second.returncode == 0, second.stderr
    after = {p: p.stat().st_mtime_ns for p in workspace.rglob('*')}
    # colcon's own log folder is the only thing a run adds or changes
    changed = sorted(str(p.relative_to(workspace)) for p in after
                     if stamps.get(p) != after[p] and 'log' not in p.relative_to(workspace).parts)
    assert changed == []
    assert (workspace / 'gen' / 'COLCON_IGNORE').is_file()
    # skipped, not rendered to compare: a stamp per package generated, in the build tree
    packages = [p for p in (workspace / 'gen').iterdir() if p.is_dir()]
    stamps = list((workspace / 'build' / '.robmosys-cache' / 'stamps').glob('*.stamp'))
    assert len(stamps) == len(packages) > 10


def test_colcon_list_leaves_a_models_errors_to_the_build(workspace):
    # colcon list names packages, as colcon-ros does of a package.xml it can
    # read: the check runs in the build (issue 16, P2; tests/test_discovery.py)
    _break_both_components(workspace)
    result = colcon(['list', '--names-only'], cwd=workspace)
    assert result.returncode == 0, result.stderr
    assert {'sender', 'receiver'} <= set(result.stdout.split())
    assert _diagnostic_lines(result.stderr) == []


def test_colcon_info_keeps_each_package_small(workspace):
    result = colcon(['info'], cwd=workspace)
    assert result.returncode == 0, result.stderr
    packages = result.stdout.count('path: ')
    assert packages > 30
    # a package's description: path, type, name, dependencies, a line of metadata
    assert len(result.stdout) / packages < 1500, result.stdout[:3000]
    assert 'checked models, 0 error(s)' in result.stdout
