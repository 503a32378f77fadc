# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""The release path: `colcon robmosys-generate --export DIR`.

The pubsub example and the dummy robot are exported, with the user's files and
robmosys_runtime, as ordinary ament packages, one per folder (the layout bloom
releases). Every package.xml passes catkin_pkg's checks and every key resolves
against an offline rosdep source. The export builds with plain colcon, every
colcon-robmosys extension blocklisted, and its systems run.
"""

from __future__ import annotations

from pathlib import Path
import re
import shutil
import sys
import xml.etree.ElementTree as ET

import pytest

from colcon_robmosys.devtools import ros_env
from colcon_robmosys.devtools.ros_env import background
from colcon_robmosys.devtools.system import wait_until
from conftest import colcon, contents, requires_ros, TEST_WORKSPACE
from harness.rosdep import ROSDEP, rosdep, rosdep_env

#: every colcon extension of colcon-robmosys (setup.cfg): none may take part
#: in building an export
BLOCKLIST = ':'.join([
    'colcon_core.package_identification.robmosys',
    'colcon_core.package_discovery.robmosys',
    'colcon_core.package_selection.robmosys',
    'colcon_core.task.build.robmosys.interfaces',
    'colcon_core.task.build.robmosys.component',
    'colcon_core.task.build.robmosys.system',
    'colcon_core.task.build.robmosys.invalid',
    'colcon_core.task.test.robmosys.interfaces',
    'colcon_core.task.test.robmosys.component',
    'colcon_core.task.test.robmosys.system',
    'colcon_core.task.test.robmosys.invalid',
    'colcon_core.verb.robmosys-generate',
    'colcon_core.verb.robmosys-import',
])

#: the packages of the two systems, and the runtime they use
EXPORTED = {
    'simple_msgs', 'publisher', 'subscriber', 'pubsub_system',
    'dummy_joint_states', 'dummy_laser', 'dummy_map_server', 'dummy_robot_monitor',
    'dummy_robot_bringup', 'robmosys_runtime',
}


def _workspace(root: Path) -> Path:
    shutil.copytree(TEST_WORKSPACE / 'src', root / 'src',
                    ignore=shutil.ignore_patterns('__pycache__'))
    return root


def _export(workspace: Path, export: Path, *selection: str):
    return colcon(['robmosys-generate', '--export', str(export), *selection], cwd=workspace,
                  timeout=300)


@pytest.fixture(scope='module')
def exported(tmp_path_factory) -> Path:
    workspace = _workspace(tmp_path_factory.mktemp('models'))
    export = tmp_path_factory.mktemp('release') / 'src'
    result = _export(workspace, export, '--packages-up-to', 'pubsub_system',
                     'dummy_robot_bringup')
    assert result.returncode == 0, result.stdout + result.stderr
    return export


def test_one_ament_package_per_folder(exported):
    from catkin_pkg.package import parse_package
    assert {p.name for p in exported.iterdir()} == EXPORTED
    assert not (exported / 'COLCON_IGNORE').exists()
    for folder in exported.iterdir():
        package = parse_package(folder / 'package.xml')
        package.validate()  # what bloom and the buildfarm check
        assert package.name == folder.name
        assert package.get_build_type() == 'ament_cmake', folder.name
        assert (folder / 'CMakeLists.txt').is_file()
        assert not (folder / 'robmosys.yaml').exists()  # no model left to read
    # the user's code comes along, at its place next to the model
    impl = exported / 'subscriber' / 'src' / 'subscriber' / 'Subscriber_impl.py'
    source = TEST_WORKSPACE / 'src' / 'subscriber' / 'src' / 'subscriber' / 'Subscriber_impl.py'
    assert impl.read_bytes() == source.read_bytes()


@pytest.mark.skipif(not ROSDEP.is_file(), reason='rosdep is not installed')
def test_every_key_resolves(exported, tmp_path):
    keys = {e.text or '' for path in exported.glob('*/package.xml')
            for e in ET.parse(path).getroot() if e.tag.endswith('depend')}
    env = rosdep_env(tmp_path, keys - EXPORTED)
    rosdep(['update'], env)
    listed = set(rosdep(['keys', '--from-paths', str(exported), '--ignore-src'],
                        env).split())
    # the export's own packages, robmosys_runtime among them, come from source
    assert listed and not listed & EXPORTED, listed
    simulated = rosdep(['install', '--simulate', '--reinstall', '--from-paths', str(exported),
                        '--ignore-src', '-y', '--os=ubuntu:noble'], env)
    assert 'ros-kilted-rclpy' in simulated, simulated
    assert 'ros-kilted-robmosys-runtime' not in simulated, simulated


@pytest.mark.integration
@requires_ros
def test_the_export_builds_and_runs_without_colcon_robmosys(exported):
    root = exported.parent
    env = ros_env.loopback_env(ros_env.free_domain_id())
    env['COLCON_EXTENSION_BLOCKLIST'] = BLOCKLIST
    colcon_bin = str(Path(sys.prefix) / 'bin' / 'colcon')
    listed = ros_env.run([colcon_bin, 'list'], env=env, cwd=root, timeout=120)
    assert listed.returncode == 0, listed.stderr
    assert {line.split('\t')[2] for line in listed.stdout.splitlines()} == {'(ros.ament_cmake)'}
    result = ros_env.run([colcon_bin, 'build', '--event-handlers', 'console_cohesion+'],
                         env=env, cwd=root, timeout=900)
    assert result.returncode == 0, result.stdout + result.stderr
    assert set(re.findall(r'Finished <<< (\w+)', result.stdout)) == EXPORTED

    install = root / 'install'
    for system, data in (('pubsub_system', 'got map data'),
                         ('dummy_robot_bringup', 'map in ')):
        bringup = install / system / 'lib' / system / 'bringup'
        with background([sys.executable, str(bringup)],
                        env=ros_env.workspace_env(install, env), stop_timeout=30) as running:
            assert wait_until(lambda: re.search(r'bringup: (\d+) of \1 managed instances active',
                                                running.output()) is not None,
                              timeout=120), running.output()
            assert wait_until(lambda: data in running.output(), timeout=30), running.output()


def test_an_export_inside_the_workspace_is_refused(tmp_path):
    workspace = _workspace(tmp_path)
    result = _export(workspace, workspace / 'release', '--packages-select', 'simple_msgs')
    assert result.returncode == 1
    assert 'error: the export folder is inside the workspace' in result.stderr, result.stderr
    assert not (workspace / 'release').exists()


def test_a_file_changed_in_the_export_is_kept(tmp_path):
    workspace = _workspace(tmp_path / 'ws')
    export = tmp_path / 'release'
    assert _export(workspace, export, '--packages-select', 'publisher').returncode == 0
    changed = export / 'robmosys_runtime' / 'robmosys_runtime' / 'system' / 'levels.py'
    changed.write_text('# patched for the release\n')
    result = _export(workspace, export, '--packages-select', 'publisher')
    assert result.returncode == 1
    assert f'{changed}:' in result.stderr and 'refusing to overwrite' in result.stderr, \
        result.stderr
    assert changed.read_text() == '# patched for the release\n'


def test_hand_written_packages_of_the_selection_are_named_once_each(tmp_path):
    workspace = _workspace(tmp_path / 'ws')
    up_to = ('--packages-up-to', 'handwritten_system', 'map_tools', 'hand_level_sensor')
    export = tmp_path / 'release' / 'src'
    result = _export(workspace, export, *up_to)
    assert result.returncode == 0, result.stdout + result.stderr
    hand_written = {'map_tools', 'hand_level_sensor', 'handwritten_nodes'}
    for name in hand_written:
        lines = [line for line in result.stdout.splitlines()
                 if line.startswith(f'not exported: {name} ')]
        assert len(lines) == 1, result.stdout
        assert lines[0].startswith(
            f'not exported: {name} (src/{name}): a hand-written package, not generated '
            'from a model: nothing to export, its sources are the package'), lines[0]
        assert lines[0].endswith('; handwritten_system depends on it') == (
            name == 'handwritten_nodes'), lines[0]
        assert name not in result.stderr
    # every package of the selection is exported or said not to be, once
    selection = colcon(['list', '--names-only', *up_to], cwd=workspace, timeout=120)
    assert selection.returncode == 0, selection.stderr
    said = re.findall(r'^(?:generated|exported|not exported:) (\w+)', result.stdout, re.M)
    assert sorted(said) == sorted(selection.stdout.split()), result.stdout
    # and the export is what the generated packages alone give
    exported = sorted(p.name for p in export.iterdir())
    assert not hand_written & set(exported)
    alone = tmp_path / 'alone' / 'src'
    result = _export(workspace, alone, '--packages-select',
                     *(set(exported) - {'robmosys_runtime'}))
    assert result.returncode == 0, result.stdout + result.stderr
    assert 'not exported' not in result.stdout
    assert sorted(p.name for p in alone.iterdir()) == exported
    assert contents(export) == contents(alone)
