# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""Discovery outlines model files, and names what the check stage would name.

colcon lists, orders and selects packages by their names and dependencies:
discovery reads those from outlines of the model files (issue 16, P2) and
leaves the check to the build. Both ways must give colcon the same packages,
with the same dependencies, for every model the check accepts; where an
outline cannot be sure, discovery checks the workspace instead.
"""

from __future__ import annotations

from pathlib import Path
import shutil
import textwrap

import pytest

from colcon_robmosys.check import find_model_files, load_workspace
from colcon_robmosys.check.index import InterfaceIndex
from colcon_robmosys.model.outline import NoOutline, outline_file
from colcon_robmosys.package_discovery.robmosys import (
    checked_descriptors, CheckedModels, outline_workspace, outlined_descriptors)
from conftest import colcon, requires_ros, TEST_WORKSPACE
from harness.fake_ament import EXAMPLE_EXTRA, fake_ament_index

MODELS = Path(__file__).parent / 'models'
INVALID = sorted((MODELS / 'invalid').glob('*.yaml'))


@pytest.fixture(scope='module')
def index(tmp_path_factory) -> InterfaceIndex:
    """Return an index of a fake ament prefix, so that no ROS is needed."""
    return fake_ament_index(tmp_path_factory.mktemp('ament_prefix'), EXAMPLE_EXTRA)


def _seen(descriptors) -> set[tuple[str, str, str, frozenset[str]]]:
    """Return what colcon reads of descriptors: path, type, name, dependencies."""
    return {(str(d.path), d.type, d.name,
             frozenset(str(x) for x in d.get_dependencies(categories=('build', ))))
            for d in descriptors}


@pytest.mark.parametrize('paths', [
    find_model_files([TEST_WORKSPACE / 'src']),
    sorted((MODELS / 'valid').glob('*.yaml')),
    sorted((MODELS / 'cpp').rglob('*.yaml'))], ids=['test_workspace', 'valid', 'cpp'])
def test_outlines_name_the_packages_and_dependencies_the_check_names(paths, index):
    paths = [p.resolve() for p in paths]
    result = load_workspace(paths, index)
    assert result.errors == []
    outlines = outline_workspace(set(paths))
    assert outlines is not None
    shared = CheckedModels(set(paths), None)
    assert _seen(outlined_descriptors(outlines, shared)) == \
        _seen(checked_descriptors(result, set(paths), shared))


@pytest.mark.parametrize('case', INVALID, ids=[p.stem for p in INVALID])
def test_an_outline_of_a_broken_model_names_the_packages_the_check_names(case, index):
    # the dependencies of a model that does not pass do not matter: its
    # package fails to build, reporting the errors
    paths = {case.resolve()}
    outlines = outline_workspace(paths)
    if outlines is None:
        return
    shared = CheckedModels(paths, None)
    checked = checked_descriptors(load_workspace(sorted(paths), index), paths, shared)
    assert {(d.type, d.name) for d in outlined_descriptors(outlines, shared)} == \
        {(d.type, d.name) for d in checked}


def _write(folder: Path, text: str) -> Path:
    folder.mkdir(parents=True, exist_ok=True)
    path = folder / 'robmosys.yaml'
    path.write_text(textwrap.dedent(text))
    return path.resolve()


COMPONENT = """\
    robmosys: 1
    defaults: {{license: MIT, maintainers: [{{name: A, email: a@example.com}}]}}
    components:
      - name: {name}
        package: {package}
        language: python
        ports:
          pOut: {{pattern: push, role: provided, type: {type}}}
    """


@pytest.mark.parametrize('text', [
    'robmosys: 1\ncomponents: [{name: A, package: a, language: python, ports: {p: 1}}]\n',
    'robmosys: 1\ncomponents: [{name: A, language: python}]\n',
    'robmosys: 1\ncomponents:\n  - &a {name: A, package: [a]}\n',
    'robmosys: 1\nsystems: {a: 1}\n',
    'robmosys: [\n',
    'robmosys: 2\ncomponents: []\n',
    '\xff\xfe',
    'robmosys: 1\ncomponents:\n  - {name: A, package: a, external: {executable: a}}\n',
], ids=['port not a mapping', 'no package', 'package not a name', 'section not a list',
        'not YAML', 'another version', 'not UTF-8', 'external models only'])
def test_what_an_outline_cannot_be_sure_of_goes_to_the_check(tmp_path, text):
    path = tmp_path / 'robmosys.yaml'
    path.write_bytes(text.encode('utf-8', 'surrogateescape') if text != '\xff\xfe'
                     else b'\xff\xfe')
    with pytest.raises(NoOutline):
        outline_file(path)
    assert outline_workspace({path}) is None


def test_two_files_of_one_package_or_a_cycle_go_to_the_check(tmp_path):
    first = _write(tmp_path / 'a', COMPONENT.format(name='A', package='a', type='b/msg/T'))
    second = _write(tmp_path / 'b', COMPONENT.format(name='B', package='a', type='c/msg/T'))
    assert outline_workspace({first}) is not None
    assert outline_workspace({first, second}) is None
    # a depends on b (its port's type), b on a: colcon could only stop
    cycle = _write(tmp_path / 'c', COMPONENT.format(name='B', package='b', type='a/msg/T'))
    assert outline_workspace({first, cycle}) is None


@requires_ros
@pytest.mark.integration
def test_colcon_list_outlines_and_the_build_checks(tmp_path):
    """A broken model's package is listed, silently; its build reports the error once."""
    shutil.copytree(TEST_WORKSPACE / 'src' / 'simple_msgs', tmp_path / 'src' / 'simple_msgs')
    broken = _write(tmp_path / 'src' / 'talker', COMPONENT.format(
        name='Talker', package='talker', type='simple_msgs/msg/NoSuchType'))
    listed = colcon(['list', '--names-only'], cwd=tmp_path)
    assert listed.returncode == 0, listed.stderr
    assert set(listed.stdout.split()) >= {'simple_msgs', 'talker'}
    assert 'error' not in listed.stderr, listed.stderr
    built = colcon(['build', '--packages-select', 'talker'], cwd=tmp_path)
    assert built.returncode != 0
    errors = [line for line in (built.stdout + built.stderr).splitlines()
              if line.startswith(f'{broken}:')]
    assert len(errors) == 1, built.stdout + built.stderr
    assert 'NoSuchType' in errors[0] and ': error: ' in errors[0]


@requires_ros
@pytest.mark.integration
def test_a_package_of_two_model_files_is_reported_by_colcon_list(tmp_path):
    """Where outlines cannot tell the packages, discovery checks, and says why, once."""
    first = _write(tmp_path / 'src' / 'a', COMPONENT.format(
        name='A', package='talker', type='std_msgs/msg/String'))
    second = _write(tmp_path / 'src' / 'b', COMPONENT.format(
        name='B', package='talker', type='std_msgs/msg/String'))
    listed = colcon(['list', '--names-only'], cwd=tmp_path)
    errors = [line for line in listed.stderr.splitlines() if ': error: ' in line]
    assert errors and len(errors) == len(set(errors)), listed.stderr
    assert all(line.startswith((f'{first}:', f'{second}:')) for line in errors), listed.stderr
    assert any('talker' in line for line in errors), listed.stderr
