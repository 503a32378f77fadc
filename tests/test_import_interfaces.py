# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""Models from installed interface packages: `colcon robmosys-import interfaces`.

Round trip: std_msgs, geometry_msgs, sensor_msgs, nav_msgs and action_msgs are
imported re-declared, the models generate the packages again, and rosidl reads
the same definitions (fields, types, bounds, defaults, constants, comments) from
the generated files as from the installed ones. One of them is built with real
rosidl and its constants read back from Python. By default a model describes the
installed package and generates nothing.
"""

from __future__ import annotations

from pathlib import Path
import shutil
import sys

import pytest
import yaml

from colcon_robmosys.check import find_model_files, load_workspace
from colcon_robmosys.check.index import InterfaceIndex
from colcon_robmosys.devtools import ros_env
from colcon_robmosys.generators import generate_package, plan_package
from conftest import colcon, requires_ros

PACKAGES = ['std_msgs', 'geometry_msgs', 'sensor_msgs', 'nav_msgs', 'action_msgs']
SHARE = Path(sys.prefix) / 'share'

pytestmark = pytest.mark.skipif(not (SHARE / 'sensor_msgs' / 'msg').is_dir(),
                                reason='the ROS 2 interface packages are not installed')


def _import(out: Path, *args: str):
    result = colcon(['robmosys-import', 'interfaces', *args, '--output-dir', str(out)],
                    cwd=out.parent, timeout=300)
    return result


def _parts(path: Path) -> list:
    """Return what rosidl reads from an interface file: its parts."""
    from rosidl_adapter.parser import (
        parse_action_file, parse_message_file, parse_service_file)
    package = path.parent.parent.name
    if path.suffix == '.msg':
        return [parse_message_file(package, str(path))]
    if path.suffix == '.srv':
        spec = parse_service_file(package, str(path))
        return [spec.request, spec.response]
    spec = parse_action_file(package, str(path))
    return [spec.goal, spec.result, spec.feedback]


def _normal(spec, banner: int = 0) -> tuple:
    """Return a part as rosidl reads it, comment lines stripped of their indentation."""
    def comment(element) -> list[str]:
        return [line.strip() for line in element.annotations.get('comment', [])]
    return (comment(spec)[banner:],
            [(str(f.type), f.name, f.default_value, comment(f)) for f in spec.fields],
            [(c.type, c.name, c.value, comment(c)) for c in spec.constants])


@pytest.fixture(scope='module')
def redeclared(tmp_path_factory) -> Path:
    out = tmp_path_factory.mktemp('import') / 'models'
    result = _import(out, *PACKAGES, '--redeclare')
    assert result.returncode == 0, result.stderr
    return out


def test_imported_models_read_like_hand_written_ones(redeclared):
    text = (redeclared / 'sensor_msgs' / 'robmosys.yaml').read_text()
    model = yaml.safe_load(text)['service_definitions'][0]
    assert 'external' not in model
    assert model['license'] and model['maintainers'] and model['version']
    status = model['communication_objects']['NavSatStatus']
    assert status['description'].startswith('Navigation Satellite fix status')
    assert status['constants']['STATUS_FIX'] == {
        'type': 'int8', 'value': 0, 'comment': 'unaugmented fix'}
    assert status['fields']['status'] == {'type': 'int8', 'default': -2,
                                          'comment': 'STATUS_UNKNOWN'}
    info = model['communication_objects']['CameraInfo']['fields']
    assert info['k']['type'] == 'float64[9]' and info['header']['type'] == 'std_msgs/Header'
    # several lines stay several lines: a block, as a person writes it
    assert 'description: |-\n' in text


def test_redeclared_packages_generate_the_same_definitions(redeclared, tmp_path):
    index = InterfaceIndex([Path(sys.prefix)])
    result = load_workspace(find_model_files([redeclared]), index)
    assert result.errors == []
    assert all(result.warnings_of(p) == [] for p in PACKAGES)
    compared = 0
    for package in PACKAGES:
        generate_package(plan_package(result.workspace, package), tmp_path / package)
        originals = sorted(p for kind in ('msg', 'srv', 'action')
                           for p in (SHARE / package / kind).glob(f'*.{kind}'))
        assert originals, package
        for original in originals:
            generated = tmp_path / package / original.parent.name / original.name
            # the generated file starts with a banner of three comment lines
            pairs = zip(_parts(original), _parts(generated))
            for index_, (theirs, ours) in enumerate(pairs):
                banner = 3 if index_ == 0 else 0
                assert _normal(ours, banner) == _normal(theirs), original
                compared += 1
    assert compared > 100


@pytest.mark.integration
@requires_ros
def test_a_redeclared_package_builds_and_reads_back(redeclared, tmp_path):
    src = tmp_path / 'src'
    shutil.copytree(redeclared / 'action_msgs', src / 'action_msgs')
    result = colcon(['build', '--event-handlers', 'console_cohesion+'], cwd=tmp_path)
    assert result.returncode == 0, result.stdout + result.stderr
    probe = ('import action_msgs.msg, action_msgs.srv; '
             'print(action_msgs.msg.__file__); '
             'print(action_msgs.msg.GoalStatus.STATUS_SUCCEEDED, '
             'action_msgs.srv.CancelGoal.Response.ERROR_GOAL_TERMINATED)')
    env = ros_env.workspace_env(tmp_path / 'install', ros_env.loopback_env(0))
    read = ros_env.run([sys.executable, '-c', probe], env=env, cwd=tmp_path, timeout=60)
    assert read.returncode == 0, read.stderr
    where, values = read.stdout.splitlines()
    assert str(tmp_path / 'install') in where  # ours, not the installed one
    assert values == '4 3'


def test_by_default_a_model_describes_the_installed_package(tmp_path):
    out = tmp_path / 'models'
    assert _import(out, 'std_msgs').returncode == 0
    model = yaml.safe_load((out / 'std_msgs' / 'robmosys.yaml').read_text())
    assert model['service_definitions'][0]['external'] is True
    component = tmp_path / 'models' / 'talker' / 'robmosys.yaml'
    component.parent.mkdir()
    component.write_text(yaml.safe_dump({'robmosys': 1, 'components': [{
        'name': 'Talker', 'package': 'talker', 'language': 'python', 'license': 'MIT',
        'maintainers': [{'name': 'A', 'email': 'a@example.com'}],
        'ports': {'pOut': {'pattern': 'push', 'role': 'provided',
                           'type': 'std_msgs/msg/String'}}}]}))
    result = load_workspace(find_model_files([out]), InterfaceIndex([Path(sys.prefix)]))
    assert result.errors == []
    # the installed package is used, not generated
    assert [m.package for m in result.workspace.generated_models] == ['talker']


def test_an_existing_model_is_never_replaced(tmp_path):
    out = tmp_path / 'models'
    (out / 'std_msgs').mkdir(parents=True)
    mine = out / 'std_msgs' / 'robmosys.yaml'
    mine.write_text('# mine\n')
    result = _import(out, 'std_msgs', 'no_such_msgs')
    assert result.returncode == 1
    assert "'no_such_msgs' is not an installed interface package" in result.stderr
    result = _import(out, 'std_msgs', 'action_msgs')
    assert result.returncode == 1
    assert f'{mine}: error: the file exists' in result.stderr or \
        'std_msgs/robmosys.yaml: error: the file exists' in result.stderr, result.stderr
    assert mine.read_text() == '# mine\n'
    assert (out / 'action_msgs' / 'robmosys.yaml').is_file()
