# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""Which files next to a model are the user's, and what generation does with them.

Without ROS: the convention of mapping/userfiles.py, the copies of a standalone
package (--output-dir), a module of the user's that takes a generated name.
"""

from __future__ import annotations

from pathlib import Path

import pytest
import yaml

from colcon_robmosys.check import find_model_files, load_workspace
from colcon_robmosys.errors import RobmosysError
from colcon_robmosys.generators import create_missing_user_files, generate_package
from colcon_robmosys.generators import plan_package
from harness.fake_ament import fake_ament_index


def _component(name: str, package: str, language: str = 'python') -> dict:
    return {'name': name, 'package': package, 'language': language,
            'license': 'Apache-2.0', 'maintainers': [{'name': 'A', 'email': 'a@example.com'}],
            'ports': {'pOut': {'pattern': 'push', 'role': 'provided',
                               'type': 'std_msgs/msg/String'}},
            'activities': {'Tick': {'period': 1.0, 'functions': ['fTick']}},
            'functions': {'fTick': {'description': 'Tick.'}}}


def _plans(tmp_path: Path, *components: dict) -> dict:
    model = tmp_path / 'src' / 'pkgs' / 'robmosys.yaml'
    model.parent.mkdir(parents=True)
    model.write_text(yaml.safe_dump({'robmosys': 1, 'components': list(components)}))
    result = load_workspace(find_model_files([tmp_path / 'src']),
                            fake_ament_index(tmp_path / 'prefix'))
    result.raise_errors()
    plans = {c['package']: plan_package(result.workspace, c['package']) for c in components}
    for plan in plans.values():
        create_missing_user_files(plan)
    return plans


def _write(root: Path, files: dict[str, str]) -> None:
    for relative, text in files.items():
        (root / relative).parent.mkdir(parents=True, exist_ok=True)
        (root / relative).write_text(text)


def test_a_standalone_package_holds_the_users_files_where_they_lie(tmp_path):
    plan = _plans(tmp_path, _component('Echo', 'echo'))['echo']
    _write(plan.model_dir, {
        'src/echo/helpers.py': '"""Helpers."""\n', 'src/echo/data/words.txt': 'hi\n',
        'config/echo.yaml': 'a: 1\n', 'launch/echo.launch.py': '"""Launch."""\n',
        'test/test_echo.py': '"""Tests."""\n', 'resource/echo': '',
        'src/echo/__pycache__/helpers.cpython-311.pyc': '', 'notes.txt': 'not listed\n'})
    out = tmp_path / 'out'
    generate_package(plan, out)
    for relative in ('src/echo/Echo_impl.py', 'src/echo/helpers.py', 'src/echo/data/words.txt',
                     'config/echo.yaml', 'launch/echo.launch.py', 'test/test_echo.py',
                     'resource/echo'):
        assert (out / relative).read_bytes() == (plan.model_dir / relative).read_bytes()
    assert not (out / 'notes.txt').exists()
    assert not list(out.rglob('__pycache__'))
    # the build tree holds none of them: the build uses them where they lie
    build = tmp_path / 'build'
    generate_package(plan, build, standalone=False)
    assert not (build / 'src').exists() and not (build / 'config').exists()
    assert (build / 'echo' / 'Echo.py').is_file()


def test_a_module_of_the_user_that_takes_a_generated_name_is_refused(tmp_path):
    plan = _plans(tmp_path, _component('Echo', 'echo'))['echo']
    mine = plan.model_dir / 'src' / 'echo' / 'Echo_main.py'
    mine.write_text('"""Mine."""\n')
    with pytest.raises(RobmosysError) as caught:
        generate_package(plan, tmp_path / 'build', standalone=False)
    assert [str(d) for d in caught.value.diagnostics] == [
        f"{mine}: error: the generated module 'echo/Echo_main.py' has this name: "
        'rename the file, the package cannot hold both']
    assert mine.read_text() == '"""Mine."""\n'


def test_components_that_share_a_file_have_a_folder_each(tmp_path):
    plans = _plans(tmp_path, _component('Echo', 'echo'), _component('Talk', 'talk', 'cpp'))
    assert plans['echo'].user_folders == (
        'src/echo', 'echo/include', 'echo/launch', 'echo/config', 'echo/resource', 'echo/test',
        'echo/cmake')
    cmake = generate_package(plans['talk'], tmp_path / 'talk')
    text = (tmp_path / 'talk' / 'CMakeLists.txt').read_text()
    assert cmake.written
    assert 'set(ROBMOSYS_USER_DIR "${ROBMOSYS_SOURCE_DIR}/talk")' in text
    assert 'set(ROBMOSYS_USER_CODE "${ROBMOSYS_SOURCE_DIR}/src/talk")' in text
    # a gtest of the user's links the component's library
    assert 'file(GLOB _user_gtests CONFIGURE_DEPENDS "${ROBMOSYS_USER_DIR}/test/*.cpp")' in text
    assert 'target_link_libraries(user_gtest ${PROJECT_NAME}_component)' in text
    # the user's CMake code, after the component's target exists
    assert text.index('file(GLOB _user_cmake CONFIGURE_DEPENDS '
                      '"${ROBMOSYS_USER_DIR}/cmake/*.cmake")') > \
        text.index('add_library(${PROJECT_NAME}_component SHARED')
