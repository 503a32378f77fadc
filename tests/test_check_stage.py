# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""One check stage: every rule runs before any file is written, once for all.

``colcon robmosys-generate --validate-only`` runs exactly the check stage and
``colcon build`` reports nothing more; a model the check accepts is mapped and
rendered without error; what only the mapping could refuse is an internal
error there, and a rule of the check.
"""

from __future__ import annotations

from dataclasses import replace
import os
from pathlib import Path
import re
import shutil
import subprocess
import sys
from typing import Iterator

import pytest

from colcon_robmosys.check import find_model_files, load_workspace
from colcon_robmosys.check.index import InterfaceIndex
from colcon_robmosys.devtools import ros_env
from colcon_robmosys.errors import RobmosysError
from colcon_robmosys.generators import plan_package
from colcon_robmosys.generators.render import render
from colcon_robmosys.mapping.backends import DEFAULT_EXECUTORS
from colcon_robmosys.mapping.component import plan_component
from colcon_robmosys.model.build import FileBuilder
from colcon_robmosys.model.files import packages_of
from colcon_robmosys.model.loader import load_file
from colcon_robmosys.model.types import Component, InterfaceKind
from conftest import requires_ros, TEST_WORKSPACE
from harness.fake_ament import EXAMPLE_EXTRA, fake_ament_index
from harness.warm_colcon import WarmColcon

MODELS = Path(__file__).parent / 'models'
INVALID = sorted((MODELS / 'invalid').glob('*.yaml'))

_WITH = re.compile(r'^# with: (.+)$', re.MULTILINE)
_DIAGNOSTIC = re.compile(r'(/\S+?:\d+:\d+: (?:error|warning): .*)$', re.MULTILINE)


@pytest.fixture(scope='module')
def index(tmp_path_factory) -> InterfaceIndex:
    """Return an index of a fake ament prefix, so that no ROS is needed."""
    return fake_ament_index(tmp_path_factory.mktemp('ament_prefix'), EXAMPLE_EXTRA)


@pytest.fixture(scope='module')
def corpus_domain_id() -> int:
    """Return one domain id for every colcon run of the corpus (none starts a node)."""
    return ros_env.free_domain_id()


@pytest.fixture(scope='module')
def corpus_prefix(tmp_path_factory) -> Path:
    """Return the fake ament prefix the corpus is written against."""
    prefix = tmp_path_factory.mktemp('corpus_prefix')
    fake_ament_index(prefix)
    return prefix


@pytest.fixture(scope='module')
def warm_colcon() -> Iterator[WarmColcon]:
    """Return colcon loaded once, forked for each of the corpus's 288 runs."""
    colcon = WarmColcon()
    yield colcon
    colcon.close()


def _corpus_env(prefix: Path, domain_id: int) -> dict[str, str]:
    """Return an environment where the interfaces installed are those of the corpus."""
    env = ros_env.loopback_env(domain_id)
    env['AMENT_PREFIX_PATH'] = str(prefix)
    return env


def _colcon(colcon: WarmColcon, args: list[str], root: Path, prefix: Path,
            domain_id: int) -> str:
    """Run colcon where the interfaces installed are those of the corpus."""
    result = colcon.run(['--log-base', str(root / 'log'), *args],
                        env=_corpus_env(prefix, domain_id), cwd=root, timeout=300)
    assert result.returncode != 0, result.stdout + result.stderr
    return result.stdout + result.stderr


def _workspace(case: Path, root: Path) -> Path:
    """Lay out a corpus case (and the files it loads with it) as a workspace."""
    text = case.read_bytes().decode('utf-8', errors='replace')
    files = [case] + [(case.parent / w).resolve() for w in _WITH.findall(text)]
    for number, path in enumerate(files):
        folder = root / 'src' / f'model{number}'
        folder.mkdir(parents=True)
        shutil.copyfile(path, folder / 'robmosys.yaml')
    return root


def _diagnostics(output: str) -> set[str]:
    return set(_DIAGNOSTIC.findall(output))


@requires_ros
@pytest.mark.integration
@pytest.mark.parametrize('case', INVALID, ids=[p.stem for p in INVALID])
def test_validate_only_reports_what_build_reports(case: Path, tmp_path: Path,
                                                  corpus_prefix: Path,
                                                  corpus_domain_id: int,
                                                  warm_colcon: WarmColcon):
    root = _workspace(case, tmp_path)
    # the valid models loaded with a case build fine: select the case's own
    try:
        selected = [name for name, _ in packages_of(load_file(case).data)]
    except RobmosysError:
        selected = []
    # a file whose models are all external makes no package but the one named
    # after its folder, which reports its errors
    selection = ['--packages-select', *selected, 'model0']
    validate = _diagnostics(_colcon(
        warm_colcon, ['robmosys-generate', '--validate-only', *selection], root,
        corpus_prefix, corpus_domain_id))
    built = _diagnostics(_colcon(
        warm_colcon, ['build', '--continue-on-error', *selection], root,
        corpus_prefix, corpus_domain_id))
    assert validate
    assert {d for d in validate if ': error: ' in d} == \
        {d for d in built if ': error: ' in d}


@requires_ros
@pytest.mark.integration
def test_warm_colcon_reports_what_the_colcon_command_reports(
        tmp_path: Path, corpus_prefix: Path, corpus_domain_id: int, warm_colcon: WarmColcon):
    # the corpus runs colcon forked from a process that loaded it once: the
    # same return code and the same lines as the command
    root = _workspace(MODELS / 'invalid' / 'port_bad_pattern.yaml', tmp_path)
    env = _corpus_env(corpus_prefix, corpus_domain_id)
    for args, code in ((['list'], 0), (['build', '--packages-select', 'puller'], 1)):
        command = ros_env.run([str(Path(sys.prefix) / 'bin' / 'colcon'), *args], env=env,
                              cwd=root, timeout=300)
        warm = warm_colcon.run(args, env=env, cwd=root, timeout=300)
        assert warm.returncode == command.returncode == code
        assert _diagnostics(warm.stdout + warm.stderr) == \
            _diagnostics(command.stdout + command.stderr) != set()
    # a run that passes its timeout is killed, and said so
    with pytest.raises(subprocess.TimeoutExpired):
        warm_colcon.run(['build', '--packages-select', 'puller'], env=env, cwd=root,
                        timeout=0.001)
    assert warm_colcon.run(['list'], env=env, cwd=root, timeout=300).returncode == 0


def _valid_workspaces() -> list[list[Path]]:
    return [find_model_files([TEST_WORKSPACE / 'src']),
            sorted((MODELS / 'valid').glob('*.yaml'))]


@pytest.mark.parametrize('paths', _valid_workspaces(), ids=['test_workspace', 'valid'])
def test_what_the_check_accepts_is_generated(paths: list[Path], index: InterfaceIndex):
    result = load_workspace(paths, index)
    assert result.errors == []
    for model in result.workspace.generated_models:
        plan = plan_package(result.workspace, model.package)
        for spec in plan.files:
            assert render(spec.template, spec.context)
        for user_file in plan.user_files:
            assert render(user_file.template, user_file.context)


CLASH = MODELS / 'invalid' / 'function_triggers_deliver_differently_{}.yaml'


@pytest.mark.parametrize('language', ['cpp', 'python'])
def test_function_run_by_different_triggers_is_refused(language: str,
                                                       index: InterfaceIndex):
    path = Path(str(CLASH).format(language))
    result = load_workspace([path], index)
    assert [(d.location.line, d.location.column) for d in result.errors] == [(21, 7)]
    assert "function 'fHandle' is run by the port 'rText'" in result.errors[0].message
    # nothing of the component reaches the mapping
    assert result.workspace.models == ()


@pytest.mark.parametrize('language', ['cpp', 'python'])
def test_mapping_calls_what_the_check_let_through_an_internal_error(language: str):
    path = Path(str(CLASH).format(language))
    models = FileBuilder(load_file(path)).build_models()
    component = models[0][1]
    assert isinstance(component, Component)
    assert component.language.value == language
    with pytest.raises(RobmosysError) as error:
        plan_component(component, DEFAULT_EXECUTORS[component.language])
    (diagnostic,) = error.value.diagnostics
    assert diagnostic.location.path == str(path)
    assert (diagnostic.location.line, diagnostic.location.column) == (21, 7)
    assert diagnostic.message.startswith('internal error: ')


def test_mapping_calls_a_port_it_cannot_map_an_internal_error(index: InterfaceIndex):
    # the schema and the builder let no event port name a message type
    result = load_workspace([MODELS / 'valid' / 'component_cpp.yaml',
                             MODELS / 'valid' / 'service_definition.yaml'], index)
    component = next(m for m in result.workspace.models if isinstance(m, Component))
    port = component.ports[0]
    broken = replace(component, ports=(replace(port, type=replace(
        port.type, kind=InterfaceKind.SRV if port.type.kind is InterfaceKind.MSG
        else InterfaceKind.MSG)),) + component.ports[1:])
    with pytest.raises(RobmosysError) as error:
        plan_component(broken, DEFAULT_EXECUTORS[broken.language])
    (diagnostic,) = error.value.diagnostics
    assert diagnostic.location == port.location
    assert diagnostic.message.startswith(f"internal error: port '{port.name}'")


@requires_ros
@pytest.mark.integration
def test_without_rosidl_adapter_one_error_and_no_build(tmp_path: Path, corpus_prefix: Path,
                                                       corpus_domain_id: int):
    """Where rosidl_adapter cannot be imported, colcon says so once, and builds nothing."""
    hidden = tmp_path / 'hidden' / 'rosidl_adapter'
    hidden.mkdir(parents=True)
    (hidden / '__init__.py').write_text("raise ImportError('hidden by the test')\n")
    root = tmp_path / 'ws'
    for name in ('service_definition', 'component_python'):
        folder = root / 'src' / name
        folder.mkdir(parents=True)
        shutil.copyfile(MODELS / 'valid' / f'{name}.yaml', folder / 'robmosys.yaml')
    env = _corpus_env(corpus_prefix, corpus_domain_id)
    env['PYTHONPATH'] = os.pathsep.join(
        [str(hidden.parent)] + [p for p in [env.get('PYTHONPATH')] if p])
    colcon = [str(Path(sys.prefix) / 'bin' / 'colcon'), '--log-base', str(root / 'log')]
    listed = ros_env.run([*colcon, 'list'], env=env, cwd=root, timeout=300)
    expected = ('colcon-robmosys: error: rosidl_adapter, the parser of .msg, .srv and '
                '.action files that checks the types and names of interfaces, cannot be '
                'imported (hidden by the test): source a ROS 2 installation')
    lines = listed.stderr.splitlines()
    assert [line for line in lines if 'error' in line.lower()] == [
        line for line in lines if line.startswith(expected)], listed.stderr
    assert len([line for line in lines if line.startswith(expected)]) == 1, listed.stderr
    # each model file is a package named after its folder, whose build fails
    assert sorted(line.split('\t')[0] for line in listed.stdout.splitlines()
                  if line.endswith('(robmosys.invalid)')) == [
        'component_python', 'service_definition'], listed.stdout
    built = ros_env.run([*colcon, 'build', '--packages-select', 'service_definition'],
                        env=env, cwd=root, timeout=300)
    assert built.returncode != 0
    output = built.stdout + built.stderr
    assert output.count(expected) == 1, output
    assert not (root / 'install' / 'service_definition').exists()
