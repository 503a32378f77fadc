# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""robmosys_runtime: tested on its own, and added to a workspace that has no underlay of it.

Its Python module runs its own tests on real rclpy; `colcon test` runs them with
its linters (ament_cpplint, ament_uncrustify, ament_flake8, ament_pep257) and,
where rclcpp exists, the gtest of its C++ headers.
"""

from __future__ import annotations

import os
from pathlib import Path
import re
import shutil
import sys
from xml.etree import ElementTree

import pytest

from colcon_robmosys.devtools import ros_env
from colcon_robmosys.mapping.common import RUNTIME_PACKAGE
from colcon_robmosys.runtime import installed_runtime, runtime_source
from conftest import build_workspace, BuiltWorkspace, requires_ros

MODEL = """\
robmosys: 1
components:
  - name: Echo
    package: echo
    language: python
    license: Apache-2.0
    maintainers: [{name: A, email: a@example.com}]
    ports:
      pOut: {pattern: push, role: provided, type: std_msgs/msg/String}
    activities:
      Tick: {period: 0.2, functions: [fTick]}
    functions:
      fTick:
        code: |
          self.get_logger().info('tick')
"""


def _model_workspace(root: Path) -> Path:
    """Write a workspace of one component model (on std_msgs: nothing else to build)."""
    model = root / 'src' / 'echo' / 'robmosys.yaml'
    model.parent.mkdir(parents=True)
    model.write_text(MODEL)
    return root / 'src'


def _colcon(args: list[str], root: Path, underlays: tuple[Path, ...] = (),
            timeout: float = 600) -> ros_env.subprocess.CompletedProcess:
    env = ros_env.loopback_env(ros_env.free_domain_id(), underlays=underlays)
    result = ros_env.run([str(Path(sys.prefix) / 'bin' / 'colcon'), *args],
                         env=env, cwd=root, timeout=timeout)
    assert result.returncode == 0, result.stdout + result.stderr
    return result


def _listed(root: Path, underlays: tuple[Path, ...] = ()) -> dict[str, Path]:
    rows = _colcon(['list'], root, underlays).stdout.splitlines()
    return {name: Path(path) for name, path, _ in (row.split('\t') for row in rows)}


def test_the_package_data_is_a_versioned_ament_package():
    source = runtime_source()
    manifest = (source / 'package.xml').read_text()
    version = re.search(r'<version>([\d.]+)</version>', manifest).group(1)
    module = (source / 'robmosys_runtime' / '__init__.py').read_text()
    assert f"__version__ = '{version}'" in module
    assert '<build_type>ament_cmake</build_type>' in manifest
    assert {p.name for p in (source / 'include' / 'robmosys_runtime').iterdir()} >= {
        'query_client.hpp', 'action_client.hpp', 'event_server.hpp', 'event_client.hpp',
        'component_node.hpp', 'main.hpp'}


def test_an_underlay_is_found_by_its_ament_index_entry(tmp_path):
    underlay = tmp_path / 'underlay'
    (underlay / 'share' / 'ament_index' / 'resource_index' / 'packages').mkdir(parents=True)
    (underlay / 'share' / 'ament_index' / 'resource_index' / 'packages' /
     RUNTIME_PACKAGE).touch()
    other = tmp_path / 'other'
    other.mkdir()
    paths = os.pathsep.join([str(other), str(underlay)])
    assert installed_runtime({'AMENT_PREFIX_PATH': paths}) == underlay.resolve()
    assert installed_runtime({'AMENT_PREFIX_PATH': str(other)}) is None
    # the install folder of the workspace being built is no underlay
    assert installed_runtime({'AMENT_PREFIX_PATH': paths}, ignored=[tmp_path]) is None


def test_the_python_module_is_typed():
    pytest.importorskip('mypy', reason='mypy is installed by `make test`')
    result = ros_env.run(
        [sys.executable, '-m', 'mypy', '--disallow-untyped-defs', '--disallow-incomplete-defs',
         '--ignore-missing-imports', '--cache-dir', os.devnull, '--explicit-package-bases',
         '-p', RUNTIME_PACKAGE],
        env=os.environ, cwd=runtime_source(), timeout=300)
    assert result.returncode == 0, result.stdout + result.stderr


@pytest.fixture(scope='module')
def without_underlay(tmp_path_factory) -> BuiltWorkspace:
    """Return a workspace of one model, built where no underlay has robmosys_runtime."""
    root = tmp_path_factory.mktemp('runtime_ws')
    src = _model_workspace(tmp_path_factory.mktemp('runtime_src'))
    return build_workspace(src, root)


@requires_ros
def test_without_underlay_the_runtime_is_added_and_built(without_underlay):
    root = without_underlay.root
    listed = _listed(root)
    assert listed[RUNTIME_PACKAGE] == runtime_source()
    order = _colcon(['list', '--topological-order', '--names-only'], root).stdout.split()
    assert order.index(RUNTIME_PACKAGE) < order.index('echo')
    index = without_underlay.install / RUNTIME_PACKAGE / 'share' / 'ament_index'
    assert (index / 'resource_index' / 'packages' / RUNTIME_PACKAGE).is_file()
    result = ros_env.run(
        [sys.executable, '-c', 'import robmosys_runtime; '
         'print(robmosys_runtime.__version__, robmosys_runtime.__file__)'],
        env=without_underlay.env(ros_env.free_domain_id()), timeout=60)
    assert result.returncode == 0, result.stderr
    assert str(without_underlay.install / RUNTIME_PACKAGE) in result.stdout
    # its own earlier build, on AMENT_PREFIX_PATH once sourced, is no underlay
    assert RUNTIME_PACKAGE in _listed(root, (without_underlay.install / RUNTIME_PACKAGE,))


@requires_ros
def test_colcon_test_runs_its_linters_and_tests(without_underlay):
    from test_cpp_system import rclcpp_missing_reason
    root = without_underlay.root
    # the C++ program of the headers is compiled by the test that runs it (colcon
    # test), not by each colcon build of a workspace that gets this package
    program = root / 'build' / RUNTIME_PACKAGE / 'test_robmosys_runtime_cpp'
    assert not program.exists()
    _colcon(['test', '--packages-select', RUNTIME_PACKAGE], root)
    results = root / 'build' / RUNTIME_PACKAGE / 'test_results' / RUNTIME_PACKAGE
    expected = {
        'cpplint.xunit.xml', 'uncrustify.xunit.xml', 'flake8.xunit.xml', 'pep257.xunit.xml',
        'test_robmosys_runtime_py.xunit.xml'}
    if rclcpp_missing_reason() is None:
        expected.add('test_robmosys_runtime_cpp.xml')
        assert program.is_file()
    assert {p.name for p in results.iterdir()} >= expected
    summary = _colcon(['test-result', '--test-result-base', str(results), '--verbose'], root)
    assert ' 0 errors, 0 failures' in summary.stdout, summary.stdout
    # the Python module's own tests ran on rclpy, every one of them
    suite = ElementTree.parse(results / 'test_robmosys_runtime_py.xunit.xml').getroot()
    suite = suite if suite.tag == 'testsuite' else suite.find('testsuite')
    defined = sum(len(re.findall(r'^def test_', path.read_text(), re.MULTILINE))
                  for path in (runtime_source() / 'test').glob('test_*.py'))
    assert defined >= 30 and int(suite.get('tests')) >= defined, \
        ElementTree.tostring(suite)[:2000]
    assert int(suite.get('skipped', 0)) == 0, ElementTree.tostring(suite)[:2000]


@requires_ros
def test_an_underlay_runtime_is_not_added(without_underlay, tmp_path):
    underlay = without_underlay.install / RUNTIME_PACKAGE
    src = _model_workspace(tmp_path / 'fresh')
    root = tmp_path / 'ws'
    shutil.copytree(src, root / 'src')
    listed = _listed(root, (underlay,))
    assert set(listed) == {'echo'}
    # and the component builds on it
    _colcon(['build'], root, (underlay,))
    assert (root / 'install' / 'echo' / 'lib' / 'echo' / 'Echo').is_file()
    assert not (root / 'install' / RUNTIME_PACKAGE).exists()


@requires_ros
def test_a_workspace_with_its_own_runtime_gets_no_second_one(tmp_path):
    src = _model_workspace(tmp_path)
    shutil.copytree(runtime_source(), src / 'vendor' / RUNTIME_PACKAGE,
                    ignore=shutil.ignore_patterns('__pycache__'))
    listed = _listed(tmp_path)
    assert (tmp_path / listed[RUNTIME_PACKAGE]).resolve() == src / 'vendor' / RUNTIME_PACKAGE
