# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""colcon sees the models' packages; the verb and the build keep user files safe."""

from __future__ import annotations

import json
from pathlib import Path
import shutil
import sys

import pytest

from conftest import colcon, requires_ros, TEST_WORKSPACE

pytestmark = requires_ros

IMPL = Path('src/subscriber/src/subscriber/Subscriber_impl.py')


@pytest.fixture
def workspace(tmp_path) -> Path:
    """Return a fresh copy of test_workspace (sources only)."""
    shutil.copytree(TEST_WORKSPACE / 'src', tmp_path / 'src',
                    ignore=shutil.ignore_patterns('__pycache__'))
    return tmp_path


def files_of(root: Path) -> dict[Path, bytes]:
    return {p.relative_to(root): p.read_bytes() for p in root.rglob('*') if p.is_file()}


def test_colcon_list_shows_one_package_per_model(workspace):
    result = colcon(['list'], cwd=workspace)
    assert result.returncode == 0, result.stderr
    rows = sorted(tuple(line.split('\t')[::2]) for line in result.stdout.splitlines())
    # several components of one model file (sender and receiver) are a package each
    assert rows == [
        ('add_client', '(robmosys.component)'),
        ('add_server', '(robmosys.component)'),
        ('cpp_client', '(robmosys.component)'),
        ('cpp_dummy_joint_states', '(robmosys.component)'),
        ('cpp_dummy_laser', '(robmosys.component)'),
        ('cpp_dummy_map_server', '(robmosys.component)'),
        ('cpp_level_sensor', '(robmosys.component)'),
        ('cpp_level_watcher', '(robmosys.component)'),
        ('cpp_publisher', '(robmosys.component)'),
        ('cpp_receiver', '(robmosys.component)'),
        ('cpp_sender', '(robmosys.component)'),
        ('cpp_server', '(robmosys.component)'),
        ('cpp_subscriber', '(robmosys.component)'),
        ('dummy_joint_states', '(robmosys.component)'),
        ('dummy_laser', '(robmosys.component)'),
        ('dummy_map_server', '(robmosys.component)'),
        ('dummy_robot_bringup', '(robmosys.system)'),
        ('dummy_robot_cpp_bringup', '(robmosys.system)'),
        ('dummy_robot_monitor', '(robmosys.component)'),
        ('example_msgs', '(robmosys.interfaces)'),
        ('examples_system', '(robmosys.system)'),
        ('fibonacci_client', '(robmosys.component)'),
        ('fibonacci_server', '(robmosys.component)'),
        ('fleet_system', '(robmosys.system)'),
        ('hand_level_sensor', '(ros.ament_cmake)'),
        # hand-written nodes, and a system of them: their models are external
        # components, which make no package of their own
        ('handwritten_nodes', '(ros.ament_python)'),
        ('handwritten_system', '(robmosys.system)'),
        ('level_sensor', '(robmosys.component)'),
        ('level_watcher', '(robmosys.component)'),
        ('map_tools', '(ros.ament_cmake)'),
        ('mixed_system', '(robmosys.system)'),
        ('mode_arm_system', '(robmosys.system)'),
        ('mode_robot_system', '(robmosys.system)'),
        ('mode_sensor', '(robmosys.component)'),
        ('publisher', '(robmosys.component)'),
        ('pubsub_system', '(robmosys.system)'),
        ('receiver', '(robmosys.component)'),
        # added from colcon-robmosys's own package data: no underlay has it
        ('robmosys_runtime', '(ros.ament_cmake)'),
        ('sender', '(robmosys.component)'),
        ('simple_msgs', '(robmosys.interfaces)'),
        ('subscriber', '(robmosys.component)'),
        ('text_relay', '(robmosys.component)'),
    ]


def test_colcon_orders_generated_packages_like_any_other(workspace):
    result = colcon(['list', '--topological-order', '--names-only'], cwd=workspace)
    order = result.stdout.split()
    assert order.index('simple_msgs') < order.index('publisher') < order.index('pubsub_system')
    assert order.index('simple_msgs') < order.index('subscriber') < order.index('pubsub_system')
    assert order.index('simple_msgs') < order.index('map_tools')
    selected = colcon(['list', '--names-only', '--packages-up-to', 'subscriber'],
                      cwd=workspace).stdout.split()
    assert sorted(selected) == ['robmosys_runtime', 'simple_msgs', 'subscriber']
    assert order.index('robmosys_runtime') < order.index('subscriber')
    assert order.index('robmosys_runtime') < order.index('hand_level_sensor')
    assert order.index('example_msgs') < order.index('hand_level_sensor')


def test_listing_writes_nothing(workspace):
    before = files_of(workspace)
    colcon(['list'], cwd=workspace)
    colcon(['graph'], cwd=workspace)
    colcon(['robmosys-generate', '--validate-only'], cwd=workspace)
    after = files_of(workspace)
    assert {p for p in after if p.parts[0] != 'log'} == set(before)
    assert all(after[p] == data for p, data in before.items())


def test_validate_only_reports_every_error_and_fails(workspace):
    model = workspace / 'src' / 'publisher' / 'robmosys.yaml'
    text = model.read_text()
    model.write_text(text.replace('functions: [fPublishing]', 'functions: [fMissing]')
                         .replace('pattern: push', 'pattern: pull'))
    before = files_of(workspace / 'src')
    result = colcon(['robmosys-generate', '--validate-only'], cwd=workspace)
    assert result.returncode != 0
    output = result.stdout + result.stderr
    assert f"{model}:13:18: error: port 'pMap': 'pattern' is 'pull', which is not one of: " \
        'push, send, query, event, action' in output
    assert files_of(workspace / 'src') == before


def test_print_schema_path_names_the_installed_schema(tmp_path):
    """Editors are pointed at the schema colcon-robmosys checks with, offline."""
    result = colcon(['robmosys-generate', '--print-schema-path'], cwd=tmp_path)
    assert result.returncode == 0
    path = Path(result.stdout.strip())
    # the file of the installed package, which outlives a checkout
    assert Path(sys.prefix) in path.parents
    source = TEST_WORKSPACE.parent / 'colcon_robmosys' / 'model' / path.name
    assert json.loads(path.read_text()) == json.loads(source.read_text())


def test_generate_creates_missing_implementation_only(workspace):
    impl = workspace / IMPL
    impl.unlink()
    result = colcon(['robmosys-generate', '--packages-select', 'subscriber'], cwd=workspace)
    assert result.returncode == 0, result.stderr
    created = impl.read_text()
    assert 'class Subscriber_impl(Subscriber):' in created
    assert 'def fListening(self, commobj) -> None:' in created

    impl.write_text('# my own work\n' + created)
    mine = impl.read_bytes()
    result = colcon(['robmosys-generate', '--output-dir', 'gen'], cwd=workspace)
    assert result.returncode == 0, result.stderr
    assert impl.read_bytes() == mine
    generated = workspace / 'gen' / 'subscriber'
    assert (generated / 'src-skel' / 'subscriber' / 'Subscriber_impl_skel.py').is_file()
    # the user's files keep their paths in a written package (docs/model-format.md)
    assert (generated / 'src' / 'subscriber' / 'Subscriber_impl.py').read_bytes() == mine
    # marked as colcon marks build/: not found as packages next time
    assert (workspace / 'gen' / 'COLCON_IGNORE').is_file()
    assert sorted(p.name for p in (workspace / 'gen').iterdir() if p.is_dir()) == [
        'add_client', 'add_server', 'cpp_client', 'cpp_dummy_joint_states', 'cpp_dummy_laser',
        'cpp_dummy_map_server', 'cpp_level_sensor', 'cpp_level_watcher', 'cpp_publisher',
        'cpp_receiver', 'cpp_sender', 'cpp_server', 'cpp_subscriber', 'dummy_joint_states',
        'dummy_laser', 'dummy_map_server', 'dummy_robot_bringup', 'dummy_robot_cpp_bringup',
        'dummy_robot_monitor', 'example_msgs', 'examples_system', 'fibonacci_client',
        'fibonacci_server', 'fleet_system', 'handwritten_system', 'level_sensor',
        'level_watcher', 'mixed_system', 'mode_arm_system', 'mode_robot_system', 'mode_sensor',
        'publisher', 'pubsub_system', 'receiver', 'sender', 'simple_msgs', 'subscriber',
        'text_relay']


def test_generate_honours_package_selection(workspace):
    result = colcon(['robmosys-generate', '--output-dir', 'gen',
                     '--packages-select', 'simple_msgs'], cwd=workspace)
    assert result.returncode == 0, result.stderr
    assert [p.name for p in (workspace / 'gen').iterdir() if p.is_dir()] == ['simple_msgs']
    assert (workspace / 'gen' / 'simple_msgs' / 'msg' / 'OGM.msg').is_file()


def test_build_without_implementation_fails_clearly(workspace):
    (workspace / IMPL).unlink()
    result = colcon(['build', '--packages-select', 'subscriber'], cwd=workspace)
    assert result.returncode != 0
    output = result.stdout + result.stderr
    assert 'the implementation file is missing' in output
    assert 'colcon robmosys-generate --packages-select subscriber' in output
    assert not (workspace / IMPL).exists()
    assert not (workspace / 'build' / 'subscriber' / 'src-gen').exists()


def test_build_names_a_function_the_implementation_lacks(workspace):
    impl = workspace / IMPL
    impl.write_text(impl.read_text().replace('def fListening', 'def fListening_old'))
    mine = impl.read_bytes()
    result = colcon(['build', '--packages-select', 'subscriber'], cwd=workspace)
    assert result.returncode != 0
    output = result.stdout + result.stderr
    assert f"{impl}:10:1: error: class 'Subscriber_impl' lacks the function " \
        "'fListening' of the model; the skeleton " \
        'src-skel/subscriber/Subscriber_impl_skel.py' in output
    assert impl.read_bytes() == mine


def test_build_of_a_broken_model_fails_and_writes_nothing(workspace):
    model = workspace / 'src' / 'subscriber' / 'robmosys.yaml'
    model.write_text(model.read_text().replace('trigger: rMap', 'trigger: rMapp'))
    result = colcon(['build', '--packages-select', 'subscriber'], cwd=workspace)
    assert result.returncode != 0
    assert f"{model}:19:18: error: activity 'HandleMsg' is triggered by unknown port " \
        "'rMapp' (known: rMap)" in result.stdout + result.stderr
    assert not (workspace / 'build' / 'subscriber' / 'src-gen').exists()


def test_colcon_uses_the_installed_package_and_its_templates(tmp_path):
    """The package works from a non-editable install: templates are package data."""
    from colcon_robmosys.devtools.ros_env import loopback_env, run
    import sys
    code = ('import colcon_robmosys\n'
            'from colcon_robmosys.generators.render import templates_dir\n'
            'print(colcon_robmosys.__file__)\n'
            'print(templates_dir())\n')
    result = run([sys.executable, '-c', code], env=loopback_env(1), cwd=tmp_path, timeout=60)
    module, templates = map(Path, result.stdout.split())
    assert module.parent != TEST_WORKSPACE.parent / 'colcon_robmosys', \
        'colcon_robmosys must not be imported from the sources'
    assert Path(sys.prefix) in module.parents
    assert templates == module.parent / 'templates'
    assert (templates / 'component_python' / 'node.py.jinja').is_file()


def test_build_of_a_model_that_is_not_yaml_fails_with_its_error(workspace):
    model = workspace / 'src' / 'subscriber' / 'robmosys.yaml'
    model.write_text('robmosys: 1\ncomponents: [\n')
    result = colcon(['build', '--packages-select', 'subscriber'], cwd=workspace)
    assert result.returncode != 0
    assert f'{model}:3:1: error: invalid YAML' in result.stdout + result.stderr
