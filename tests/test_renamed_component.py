# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""A component renamed in the model: the implementation files it leaves are one error.

Issue 24: renaming ``SurvivorCpp`` to ``RenamedCpp`` left ``SurvivorCpp_impl.{hpp,cpp}``
compiled with the package, which failed on ``sv_cpp/SurvivorCpp.hpp``; a Python
component's ``_impl.py`` was silently left out of its node, and ``colcon robmosys-generate``
made a fresh, empty implementation beside the user's. Now `colcon build` and `colcon
robmosys-generate` stop before anything is made or compiled, with one line at the
component's name in the model that names the files and the rename to make.
"""

from __future__ import annotations

import os
from pathlib import Path

import pytest

from colcon_robmosys.check import find_model_files, load_workspace
from colcon_robmosys.check.index import InterfaceIndex
from colcon_robmosys.errors import RobmosysError
from colcon_robmosys.generators import create_missing_user_files, generate_package
from colcon_robmosys.generators import PackageFiles, plan_package, StampStore
from colcon_robmosys.generators import unchanged_package
from colcon_robmosys.generators.usercode import orphan_problems
from conftest import assert_no_traceback, colcon, requires_ros
from harness.fake_ament import fake_ament_index

MODEL = """\
robmosys: 1
components:
  - name: {name}
    package: {package}
    language: {language}
    license: Apache-2.0
    maintainers: [{{name: A, email: a@example.com}}]
    ports:
      pOut: {{pattern: push, role: provided, type: std_msgs/msg/String}}
    activities:
      Tick: {{period: 0.2, functions: [fTick]}}
    functions:
      fTick:
        description: Publish a text.
"""


class Workspace:
    """One component, its model and its implementation files."""

    def __init__(self, root: Path, name: str, package: str, language: str):
        self.root, self.name, self.package, self.language = root, name, package, language
        self.model = root / 'src' / package / 'robmosys.yaml'
        self.code = self.model.parent / 'src' / package
        self.model.parent.mkdir(parents=True)
        self.save()

    def save(self) -> None:
        self.model.write_text(MODEL.format(
            name=self.name, package=self.package, language=self.language))

    def impl(self, name: str | None = None) -> list[Path]:
        suffixes = ('.py',) if self.language == 'python' else ('.hpp', '.cpp')
        return [self.code / f'{name or self.name}_impl{s}' for s in suffixes]

    def rename(self, name: str) -> str:
        """Rename the component in the model; return where the model names it."""
        self.name = name
        self.save()
        lines = self.model.read_text().splitlines()
        line = next(i for i, text in enumerate(lines) if text.endswith(f'name: {name}'))
        return f'{self.model}:{line + 1}:{lines[line].index(name) + 1}'

    def user_files(self) -> dict[Path, bytes]:
        return {p: p.read_bytes() for p in sorted(self.code.rglob('*')) if p.is_file()}


def _errors(output: str) -> list[str]:
    return [line for line in output.splitlines() if ': error: ' in line]


def _ok(result) -> None:
    assert result.returncode == 0, result.stdout + result.stderr


def _refused(result, error: str, package: str, root: Path) -> None:
    """Assert a colcon run stopped on the one error, before anything ran for the package."""
    output = result.stdout + result.stderr
    assert result.returncode != 0, output
    assert _errors(output) == [error], output
    assert 'fatal error' not in output and 'CMake Error' not in output, output
    assert_no_traceback(output)
    # no command (cmake, a compiler) ran for the package: colcon logs each one
    assert not (root / 'log' / 'latest' / package / 'command.log').exists(), output


@requires_ros
def test_a_python_component_renamed_is_one_error_until_its_file_is_renamed(tmp_path):
    ws = Workspace(tmp_path, 'SurvivorPy', 'sv_py', 'python')
    _ok(colcon(['robmosys-generate'], cwd=tmp_path))
    [impl] = ws.impl()
    impl.write_text(impl.read_text().replace(
        "warning('fTick is not implemented yet')", "info('my own fTick')"))
    _ok(colcon(['build'], cwd=tmp_path))
    mine = ws.user_files()

    where = ws.rename('RenamedPy')
    error = (f"{where}: error: {impl}: the implementation of a component 'SurvivorPy', "
             "which the package 'sv_py' does not have; was 'SurvivorPy' renamed to "
             "'RenamedPy'? rename SurvivorPy_impl.py to RenamedPy_impl.py, and 'SurvivorPy' "
             "in it to 'RenamedPy'")
    for verb in ('build', 'robmosys-generate'):
        _refused(colcon([verb], cwd=tmp_path), error, 'sv_py', tmp_path)
        assert ws.user_files() == mine, 'the user files are as they were, and no new one'

    # done as it says, the build passes with the user's code
    [renamed] = ws.impl()
    renamed.write_text(impl.read_text().replace('SurvivorPy', 'RenamedPy'))
    impl.unlink()
    _ok(colcon(['build'], cwd=tmp_path))
    # (the first build's SurvivorPy_impl.py stays installed: colcon removes nothing)
    installed = list((tmp_path / 'install' / 'sv_py').rglob('RenamedPy_impl.py'))
    assert [p.read_text() for p in installed] == [renamed.read_text()]
    assert 'my own fTick' in renamed.read_text()

    # the old file back (a checkout, say), the model as it was at the last build:
    # the generation the stamps would skip reports it
    impl.write_bytes(mine[impl])
    error = (f"{where}: error: {impl}: the implementation of a component 'SurvivorPy', "
             "which the package 'sv_py' does not have; was 'SurvivorPy' renamed to "
             "'RenamedPy'? move what you need of SurvivorPy_impl.py into RenamedPy_impl.py, "
             'then delete it')
    _refused(colcon(['build'], cwd=tmp_path), error, 'sv_py', tmp_path)


@requires_ros
def test_a_cpp_component_renamed_is_one_error_before_any_compiler(tmp_path):
    from test_cpp_system import rclcpp_missing_reason
    ws = Workspace(tmp_path, 'SurvivorCpp', 'sv_cpp', 'cpp')
    _ok(colcon(['robmosys-generate'], cwd=tmp_path))
    hpp, cpp = ws.impl()
    cpp.write_text(cpp.read_text().replace(
        'RCLCPP_WARN(get_logger(), "fTick is not implemented yet");',
        'RCLCPP_INFO(get_logger(), "the user\'s own fTick");'))
    env = {}
    if rclcpp_missing_reason():
        # colcon skips a C++ component where no prefix has rclcpp: one that seems
        # to have it lets the build task run, and stop before CMake would look
        prefix = tmp_path / 'seems_to_have_rclcpp'
        markers = prefix / 'share' / 'ament_index' / 'resource_index' / 'packages'
        markers.mkdir(parents=True)
        for package in ('rclcpp', 'rclcpp_lifecycle', 'rclcpp_components', 'rclcpp_action'):
            (markers / package).touch()
        env['CMAKE_PREFIX_PATH'] = os.pathsep.join(
            filter(None, [os.environ.get('CMAKE_PREFIX_PATH'), str(prefix)]))
    else:
        _ok(colcon(['build'], cwd=tmp_path, timeout=1200))
    mine = ws.user_files()

    where = ws.rename('RenamedCpp')
    error = (f'{where}: error: {hpp}, {cpp}: the implementation of a component '
             "'SurvivorCpp', which the package 'sv_cpp' does not have; was 'SurvivorCpp' "
             "renamed to 'RenamedCpp'? rename SurvivorCpp_impl.hpp/.cpp to "
             "RenamedCpp_impl.hpp/.cpp, and 'SurvivorCpp' in them to 'RenamedCpp'")
    for verb in ('build', 'robmosys-generate'):
        _refused(colcon([verb], cwd=tmp_path, extra_env=env), error, 'sv_cpp', tmp_path)
        assert ws.user_files() == mine, 'the user files are as they were, and no new one'


# The variants of the message, on the generators alone (no colcon, no ROS 2).

@pytest.fixture(scope='module')
def index(tmp_path_factory) -> InterfaceIndex:
    return fake_ament_index(tmp_path_factory.mktemp('ament_prefix'))


@pytest.fixture
def workspace(tmp_path) -> Workspace:
    return Workspace(tmp_path, 'Old', 'pkg', 'python')


def _plan(ws: Workspace, index: InterfaceIndex) -> PackageFiles:
    result = load_workspace(find_model_files([ws.root / 'src']), index)
    result.raise_errors()
    return plan_package(result.workspace, ws.package)


def _orphans(ws: Workspace, index: InterfaceIndex) -> list[str]:
    return [str(d) for d in orphan_problems(_plan(ws, index))]


def test_an_implementation_file_of_the_user_s_that_is_no_component_s_is_left_alone(
        workspace, index):
    create_missing_user_files(_plan(workspace, index))
    # a module of the user's named like one, not made like one
    (workspace.code / 'Parser_impl.py').write_text('class ParserImpl:\n    pass\n')
    (workspace.code / 'Garbage_impl.py').write_bytes(b'\xff\xfe')
    assert _orphans(workspace, index) == []


def test_the_message_says_what_to_do_with_each_state_of_the_new_files(workspace, index):
    plan = _plan(workspace, index)
    create_missing_user_files(plan)
    [old] = workspace.impl()
    where = workspace.rename('New')
    head = (f"{where}: error: {old}: the implementation of a component 'Old', which the "
            "package 'pkg' does not have; was 'Old' renamed to 'New'? ")
    rename = "rename Old_impl.py to New_impl.py, and 'Old' in it to 'New'"
    assert _orphans(workspace, index) == [head + rename]

    # what a generation made before it refused: nothing of the user's
    [new] = workspace.impl()
    new.write_text(old.read_text().replace('Old', 'New'))
    assert _orphans(workspace, index) == [
        head + rename + ' (over New_impl.py, made from the model since)']

    # the user's code in both
    new.write_text(new.read_text() + '# mine\n')
    assert _orphans(workspace, index) == [
        head + 'move what you need of Old_impl.py into New_impl.py, then delete it']

    # two components left behind
    (workspace.code / 'Older_impl.py').write_text(
        old.read_text().replace('Old', 'Older'))
    assert _orphans(workspace, index) == [
        f"{where}: error: {old}, {workspace.code / 'Older_impl.py'}: the implementations "
        "of components 'Old', 'Older', which the package 'pkg' does not have; the component "
        "of 'pkg' is 'New': move what you need of them into New_impl.py, then delete them"]

    # a component without functions of the user's has no file to rename to
    (workspace.code / 'Older_impl.py').unlink()
    workspace.model.write_text(workspace.model.read_text().replace(
        'description: Publish a text.', 'code: pass'))
    assert _orphans(workspace, index) == [
        f"{where}: error: {old}: the implementation of a component 'Old', which the "
        "package 'pkg' does not have; its component 'New' has no function of the user's: "
        "delete it, or name the component 'Old' again"]


def test_generation_refuses_and_makes_no_file_beside_the_one_left_behind(workspace, index):
    plan = _plan(workspace, index)
    create_missing_user_files(plan)
    before = workspace.user_files()
    workspace.rename('New')
    plan = _plan(workspace, index)
    with pytest.raises(RobmosysError) as raised:
        create_missing_user_files(plan)
    assert len(raised.value.diagnostics) == 1
    with pytest.raises(RobmosysError) as raised:
        generate_package(plan, workspace.root / 'out')
    # one line: not also "New_impl.py is missing: run colcon robmosys-generate"
    assert len(raised.value.diagnostics) == 1, raised.value
    assert workspace.user_files() == before
    assert not (workspace.root / 'out').exists()


def test_stamps_do_not_skip_a_generation_with_a_file_left_behind(workspace, index):
    create_missing_user_files(_plan(workspace, index))
    [old] = workspace.impl()
    content = old.read_bytes()
    old.unlink()
    workspace.rename('New')
    plan = _plan(workspace, index)
    create_missing_user_files(plan)
    stamps, out = StampStore(workspace.root / 'stamps'), workspace.root / 'out'
    generate_package(plan, out, stamps=stamps, fingerprint='model', standalone=False)
    assert unchanged_package(out, stamps, 'model') is not None
    # the stamp lists the implementation files there: a new one is seen
    # without the plan
    old.write_bytes(content)
    assert unchanged_package(out, stamps, 'model') is None
    with pytest.raises(RobmosysError):
        generate_package(plan, out, stamps=stamps, fingerprint='model', standalone=False)
