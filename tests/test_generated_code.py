# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""The generated packages: ROS code standards, determinism, launch files."""

from __future__ import annotations

import ast
import json
from pathlib import Path
import shutil
import subprocess
import sys

import pytest
import yaml

from colcon_robmosys.check import find_model_files, load_workspace
from colcon_robmosys.check.index import InterfaceIndex
from colcon_robmosys.generators import generate_package
from colcon_robmosys.generators import plan_package
from conftest import TEST_WORKSPACE
from harness.launch_files import read_launch_file


def generate_workspace(src: Path, out: Path) -> dict[str, object]:
    """Generate every package of a workspace's models into out/<package>."""
    result = load_workspace(find_model_files([src]), InterfaceIndex([Path(sys.prefix)]))
    result.raise_errors()
    return {m.package: generate_package(plan_package(result.workspace, m.package),
                                        out / m.package)
            for m in result.workspace.generated_models}


@pytest.fixture(scope='module')
def generated(tmp_path_factory) -> Path:
    src = tmp_path_factory.mktemp('src')
    shutil.copytree(TEST_WORKSPACE / 'src', src, dirs_exist_ok=True)
    out = tmp_path_factory.mktemp('generated')
    generate_workspace(src, out)
    return out


def python_files(root: Path) -> list[Path]:
    files = sorted(root.rglob('*.py'))
    files += sorted(p for p in root.glob('*/scripts/*') if p.is_file())
    return files


def _linter(name: str) -> str:
    path = shutil.which(name, path=str(Path(sys.prefix) / 'bin'))
    if path is None:
        pytest.skip(f'{name} is not installed (ros-{name.replace("_", "-")} on PyPI)')
    return path


@pytest.mark.parametrize('linter', ['ament_flake8', 'ament_pep257'])
def test_ament_python_linters_pass(generated, linter):
    files = python_files(generated)
    assert len(files) > 10
    result = subprocess.run([_linter(linter), *map(str, files)], capture_output=True,
                            text=True, timeout=300)
    assert result.returncode == 0, result.stdout + result.stderr


def test_package_xml_files_are_valid_for_catkin_pkg(generated):
    """Every package of test_workspace has a package.xml catkin_pkg reads as the model says."""
    from catkin_pkg.package import parse_package
    src = TEST_WORKSPACE / 'src'
    result = load_workspace(find_model_files([src]), InterfaceIndex([Path(sys.prefix)]))
    models = {m.package: m for m in result.workspace.generated_models}
    assert sorted(p.parent.name for p in generated.glob('*/package.xml')) == sorted(models)
    for name, model in models.items():
        warnings: list[str] = []
        package = parse_package(generated / name / 'package.xml', warnings=warnings)
        package.validate(warnings=warnings)  # what ament_cmake and bloom check
        assert warnings == [], name
        assert package.name == name
        assert package.get_build_type() == 'ament_cmake'
        assert package.package_format == 3
        info = model.info
        assert (package.version, package.description) == (info.version, info.description)
        assert [str(lic) for lic in package.licenses] == [info.license]
        assert [(m.name, m.email) for m in package.maintainers] == \
            [(m.name, m.email) for m in info.maintainers]
        depends = {d.name for d in package.build_depends + package.exec_depends}
        assert set(info.depends) <= depends, name


def test_package_xml_files_pass_ament_xmllint(generated):
    # ament_xmllint is not among the ros-* wheels: here catkin_pkg checks the files
    # (the test above); on a ROS 2 install with ament_xmllint this runs too
    ament_xmllint = shutil.which('ament_xmllint') or shutil.which(
        'ament_xmllint', path=str(Path(sys.prefix) / 'bin'))
    if ament_xmllint is None:
        pytest.skip('ament_xmllint is not installed (not on PyPI; it comes with a ROS 2 '
                    'install): test_package_xml_files_are_valid_for_catkin_pkg checks them')
    files = sorted(generated.glob('*/package.xml'))
    result = subprocess.run([ament_xmllint, *map(str, files)], capture_output=True,
                            text=True, timeout=300)
    assert result.returncode == 0, result.stdout + result.stderr


def test_system_package_depends_on_what_it_launches(generated):
    from catkin_pkg.package import parse_package
    package = parse_package(generated / 'pubsub_system' / 'package.xml')
    exec_depends = {d.name for d in package.exec_depends}
    assert {'publisher', 'subscriber', 'launch_ros', 'lifecycle_msgs'} <= exec_depends


def test_events_and_actions_become_action_files(generated):
    """An event: goal = activation + single, result = feedback = event."""
    from catkin_pkg.package import parse_package
    package = generated / 'example_msgs'
    body = [line for line in (package / 'action' / 'LevelAbove.action').read_text().split('\n')
            if line and not line.startswith('#')]
    assert body == ['int32 threshold', 'bool single false', '---', 'int32 level', '---',
                    'int32 level']
    assert (package / 'action' / 'Fibonacci.action').is_file()
    assert 'action_msgs' in {d.name for d in parse_package(package / 'package.xml').build_depends
                             + parse_package(package / 'package.xml').exec_depends}
    assert '"action/LevelAbove.action"' in (package / 'CMakeLists.txt').read_text()


def test_every_generated_file_has_a_banner(generated):
    for path in generated.rglob('*'):
        user_copy = path.name.endswith(('_impl.py', '_impl.hpp', '_impl.cpp')) and \
            'src-skel' not in path.parts
        # the model's copy is the user's text as it is, so that its lines are the
        # model's: the file beside it says that it is generated
        model_copy = path.parts[-2:] == ('robmosys', 'robmosys.yaml')
        if model_copy:
            assert 'Generated by colcon-robmosys' in \
                (path.parent / 'source.yaml.in').read_text(), path
        elif path.is_file() and path.name != '.robmosys-generated' and not user_copy:
            assert 'Generated by colcon-robmosys' in path.read_text(), path


def test_the_installed_model_is_the_model_file_as_it_is(generated):
    # its lines are the model file's: the system manager's reports point at them
    for package in ('pubsub_system', 'publisher', 'simple_msgs'):
        model = TEST_WORKSPACE / 'src' / package / 'robmosys.yaml'
        assert (generated / package / 'robmosys' / 'robmosys.yaml').read_bytes() == \
            model.read_bytes(), package
        # where the model file was is said at the build (ROBMOSYS_MODEL_FILE, relative to
        # the install): the generated sources hold no path
        source = (generated / package / 'robmosys' / 'source.yaml.in').read_text()
        assert source.endswith("\nsource: '@ROBMOSYS_MODEL_SOURCE@'\n"), source


def test_output_is_deterministic_and_location_free(tmp_path):
    outputs = []
    for name in ('first', 'second'):
        src = tmp_path / name / 'deeper' / 'src'
        shutil.copytree(TEST_WORKSPACE / 'src', src)
        generate_workspace(src, tmp_path / name / 'out')
        outputs.append(tmp_path / name / 'out')
    first = {p.relative_to(outputs[0]): p.read_bytes()
             for p in outputs[0].rglob('*') if p.is_file()}
    second = {p.relative_to(outputs[1]): p.read_bytes()
              for p in outputs[1].rglob('*') if p.is_file()}
    assert first == second
    assert not any(str(tmp_path).encode() in data for data in first.values())


def test_regeneration_rewrites_nothing(tmp_path):
    shutil.copytree(TEST_WORKSPACE / 'src', tmp_path / 'src')
    generate_workspace(tmp_path / 'src', tmp_path / 'out')
    stamps = {p: p.stat().st_mtime_ns for p in (tmp_path / 'out').rglob('*') if p.is_file()}
    reports = generate_workspace(tmp_path / 'src', tmp_path / 'out')
    assert all(not r.written and not r.removed for r in reports.values())
    assert stamps == {p: p.stat().st_mtime_ns
                      for p in (tmp_path / 'out').rglob('*') if p.is_file()}


def _expected_nodes():
    result = load_workspace(find_model_files([TEST_WORKSPACE / 'src']),
                            InterfaceIndex([Path(sys.prefix)]))
    system = result.workspace.model('pubsub_system')
    return system, {
        'publisher': ('publisher', 'PeriodicPublisher', (('pMap', '/publisher/pMap'),)),
        'subscriber': ('subscriber', 'Subscriber', (('rMap', '/publisher/pMap'),)),
    }


@pytest.mark.parametrize('launch_file', [
    f'pubsub_system{instance}{kind}.launch.py' for instance in ('', '.publisher', '.subscriber')
    for kind in ('', '.nodes')])
def test_launch_files_follow_the_system_model(generated, launch_file):
    system, expected = _expected_nodes()
    share = generated / 'pubsub_system'
    nodes = read_launch_file(share / 'launch' / launch_file, share)
    parts = launch_file.removesuffix('.launch.py').removesuffix('.nodes').split('.')
    instance = parts[1] if len(parts) == 2 else None
    wanted = [i.name for i in system.instances if instance in (None, i.name)]
    assert [n.name for n in nodes] == wanted
    for node in nodes:
        assert (node.package, node.executable, node.remappings) == expected[node.name]
        assert node.namespace == ''
        assert node.params_files == (share / 'cfg' / 'params.yaml',)
        assert node.extra == {'output': 'screen'}


def test_params_file_holds_the_overrides(generated):
    params = yaml.safe_load((generated / 'pubsub_system' / 'cfg' / 'params.yaml').read_text())
    assert params == {'/publisher': {'ros__parameters': {'indoor': True, 'noOfScans': 3}}}


def test_integer_override_of_a_double_parameter_is_written_as_double(tmp_path):
    """ROS 2 refuses an integer for a double parameter: the params file says 2.0."""
    shutil.copytree(TEST_WORKSPACE / 'src', tmp_path / 'src')
    publisher = tmp_path / 'src' / 'publisher' / 'robmosys.yaml'
    publisher.write_text(publisher.read_text().replace(
        '    parameters:\n', '    parameters:\n      gain: {type: double, default: 0.5}\n'))
    system = tmp_path / 'src' / 'pubsub_system' / 'robmosys.yaml'
    system.write_text(system.read_text().replace('noOfScans: 3}', 'noOfScans: 3, gain: 2}'))
    generate_workspace(tmp_path / 'src', tmp_path / 'out')
    params = (tmp_path / 'out' / 'pubsub_system' / 'cfg' / 'params.yaml').read_text()
    assert yaml.safe_load(params)['/publisher']['ros__parameters'] == \
        {'indoor': True, 'noOfScans': 3, 'gain': 2.0}
    assert 'gain: 2.0' in params


LONG_TEXT = ('A sentence long enough to pass the line length of ament_flake8 on its own, '
             'with "quotes", \'apostrophes\' and a backslash \\ in it')
LONG_TEXTS_MODEL = f"""\
robmosys: 1
components:
  - name: Verbose
    package: verbose
    language: python
    description: {json.dumps(LONG_TEXT + ' (the first line of the description)')}
    license: Apache-2.0
    maintainers: [{{name: Example, email: example@example.com}}]
    parameters:
      label: {{type: string, default: {json.dumps(LONG_TEXT * 2)},
               description: {json.dumps(LONG_TEXT)}}}
      names: {{type: 'string[]', default: [{json.dumps(LONG_TEXT)}, b, c]}}
      gains: {{type: 'double[]', default: [{', '.join(['0.123456789012345'] * 8)}]}}
      ratio: {{type: double, default: 0.5,
               range: {{from: 0.000123456789012345, to: 1234567.12345678901, step: 0.0}}}}
"""


def test_long_model_texts_fit_the_linters_and_keep_their_values(tmp_path):
    (tmp_path / 'src' / 'verbose').mkdir(parents=True)
    (tmp_path / 'src' / 'verbose' / 'robmosys.yaml').write_text(LONG_TEXTS_MODEL)
    generate_workspace(tmp_path / 'src', tmp_path / 'out')
    node = tmp_path / 'out' / 'verbose' / 'verbose' / 'Verbose.py'
    for linter in ('ament_flake8', 'ament_pep257'):
        result = subprocess.run([_linter(linter), str(node)], capture_output=True,
                                text=True, timeout=300)
        assert result.returncode == 0, result.stdout + result.stderr
    tree = ast.parse(node.read_text())
    declared = {ast.literal_eval(call.args[0]): ast.literal_eval(call.args[1])
                for call in ast.walk(tree) if isinstance(call, ast.Call)
                and ast.unparse(call.func) == 'self.declare_parameter'}
    assert declared == {'label': LONG_TEXT * 2, 'names': [LONG_TEXT, 'b', 'c'],
                        'gains': [0.123456789012345] * 8, 'ratio': 0.5}
    descriptions = [ast.literal_eval(k.value) for call in ast.walk(tree)
                    if isinstance(call, ast.Call)
                    and ast.unparse(call.func) == 'ParameterDescriptor'
                    for k in call.keywords if k.arg == 'description']
    assert LONG_TEXT in descriptions
    cls = next(n for n in tree.body if isinstance(n, ast.ClassDef) and n.name == 'Verbose')
    assert LONG_TEXT in ' '.join(ast.get_docstring(cls).split())


@pytest.mark.parametrize('text', [
    'Plain text.', 'A backslash \\ and \\n stay as they are.', 'Quotes """ inside.',
    "Both \"\"\" and ''' inside.", 'A backslash \\ with """ quotes.',
    'Summary.\n\nBody with \\ and """ and a long line ' + 'x' * 120 + '.',
])
def test_docstrings_keep_the_model_text_and_pass_pep257(tmp_path, text):
    from colcon_robmosys.generators.filters import py_docstring
    source = f'"""Module."""\n\n\nclass C:\n    {py_docstring(text, 4)}\n'
    tree = ast.parse(source)
    assert ' '.join(ast.get_docstring(tree.body[1]).split()) == ' '.join(text.split())
    module = tmp_path / 'module.py'
    module.write_text(source)
    both = '"""' in text and "'''" in text
    result = subprocess.run([_linter('ament_pep257'), str(module)], capture_output=True,
                            text=True, timeout=300)
    # with both kinds of triple quotes only escapes are left (and D301 says so)
    assert (result.returncode == 0) != both, result.stdout + result.stderr


def _class_constant(path: Path, name: str) -> object:
    """Return the value of a constant assigned in the class a module is named after."""
    cls = next(n for n in ast.parse(path.read_text()).body
               if isinstance(n, ast.ClassDef) and n.name == path.stem)
    return next(ast.literal_eval(n.value) for n in cls.body if isinstance(n, ast.Assign)
                and [t.id for t in n.targets if isinstance(t, ast.Name)] == [name])


@pytest.mark.parametrize('node_file, threads', [
    # two activities and a query client, whose blocking call waits on one thread
    # while the answer arrives on another; the same for an action client
    ('add_client/add_client/AddClient.py', 4),
    ('fibonacci_client/fibonacci_client/FibonacciClient.py', 4),
    # one activity: rclpy's default (a thread per CPU) is what it gets
    ('add_server/add_server/AddServer.py', 2),
    ('subscriber/subscriber/Subscriber.py', 2),
])
def test_a_node_asks_for_a_thread_per_callback_group_and_one_more(
        generated, node_file, threads):
    # robmosys_runtime.run spins it with max(CPUs, min_threads) threads, as the
    # C++ process does (robmosys_runtime::run's min_threads)
    assert _class_constant(generated / node_file, 'min_threads') == threads
