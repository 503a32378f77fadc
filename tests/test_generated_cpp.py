# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""Generated C++ components: golden trees, ROS 2 C++ style, the user's files.

Regenerate the golden trees after an intended change of the C++ generator with
``ROBMOSYS_UPDATE_GOLDEN=1 make test PYTEST_ARGS='-k golden'`` and review the
result as a diff (``git diff tests/golden``) before committing it.
"""

from __future__ import annotations

import os
from pathlib import Path
import shutil
import subprocess
import sys

import pytest

from colcon_robmosys.check import find_model_files, load_workspace
from colcon_robmosys.check.index import InterfaceIndex
from colcon_robmosys.errors import RobmosysError
from colcon_robmosys.generators import create_missing_user_files, generate_package
from colcon_robmosys.generators import plan_package
from colcon_robmosys.generators.filters import cpp_comment, cpp_str
from colcon_robmosys.mapping.backends.cpp.parameters import string_lines
from colcon_robmosys.model.types import Component, Language
from conftest import contents, TEST_WORKSPACE

GOLDEN = Path(__file__).resolve().parent / 'golden'
#: A component with every port and parameter kind, beside the examples.
CPP_MODELS = Path(__file__).resolve().parent / 'models' / 'cpp'
UPDATE = os.environ.get('ROBMOSYS_UPDATE_GOLDEN') == '1'


def _load(*src: Path):
    result = load_workspace(find_model_files(list(src)), InterfaceIndex([Path(sys.prefix)]))
    result.raise_errors()
    return result.workspace


def _cpp_packages(workspace) -> list[str]:
    return sorted(m.package for m in workspace.models
                  if isinstance(m, Component) and m.language is Language.CPP)


def _copy_models(src: Path) -> Path:
    shutil.copytree(TEST_WORKSPACE / 'src', src, dirs_exist_ok=True)
    shutil.copytree(CPP_MODELS, src / 'cpp_models')
    return src


CPP_PACKAGES = _cpp_packages(_load(TEST_WORKSPACE / 'src', CPP_MODELS))


@pytest.fixture(scope='module')
def generated_cpp(tmp_path_factory) -> Path:
    """Generate the C++ packages of test_workspace and tests/models/cpp (copies)."""
    workspace = _load(_copy_models(tmp_path_factory.mktemp('src')))
    out = tmp_path_factory.mktemp('generated_cpp')
    for package in _cpp_packages(workspace):
        plan = plan_package(workspace, package)
        # all_ports comes without code of its own: the skeleton is its code
        create_missing_user_files(plan)
        generate_package(plan, out / package)
    return out


def test_examples_hold_every_cpp_pattern():
    assert CPP_PACKAGES == ['all_ports', 'cpp_client', 'cpp_dummy_joint_states',
                            'cpp_dummy_laser', 'cpp_dummy_map_server', 'cpp_level_sensor',
                            'cpp_level_watcher', 'cpp_publisher', 'cpp_receiver', 'cpp_sender',
                            'cpp_server', 'cpp_subscriber']


@pytest.mark.parametrize('package', CPP_PACKAGES)
def test_golden(generated_cpp, package):
    """The generated tree is the reviewed one, byte for byte."""
    actual = contents(generated_cpp / package)
    golden_dir = GOLDEN / package
    if UPDATE:
        shutil.rmtree(golden_dir, ignore_errors=True)
        for relative, data in actual.items():
            path = golden_dir / relative
            path.parent.mkdir(parents=True, exist_ok=True)
            path.write_bytes(data)
    expected = contents(golden_dir)
    assert sorted(actual) == sorted(expected), \
        'the generated files differ from tests/golden: see ' \
        'tests/test_generated_cpp.py for how to regenerate them'
    for relative in expected:
        assert actual[relative] == expected[relative], \
            f'{package}/{relative} differs from tests/golden ' \
            '(ROBMOSYS_UPDATE_GOLDEN=1 regenerates it)'


def test_layout_of_the_reference(generated_cpp):
    files = set(contents(generated_cpp / 'cpp_subscriber'))
    assert files == {
        '.robmosys-generated', 'CMakeLists.txt', 'package.xml',
        'src-gen/cpp_subscriber/Subscriber.hpp', 'src-gen/cpp_subscriber/Subscriber.cpp',
        'src-gen/cpp_subscriber/Subscriber_main.cpp',
        'src-skel/cpp_subscriber/Subscriber_impl.hpp',
        'src-skel/cpp_subscriber/Subscriber_impl.cpp',
        'src/cpp_subscriber/Subscriber_impl.hpp', 'src/cpp_subscriber/Subscriber_impl.cpp',
        # the model, installed for the workspaces that build on this one, and what says
        # that it is generated and where it was built from (configured by CMake)
        'robmosys/robmosys.yaml', 'robmosys/source.yaml.in',
    }
    # the skeleton is regenerated but never built
    cmake = (generated_cpp / 'cpp_subscriber' / 'CMakeLists.txt').read_text()
    assert 'src-skel' not in cmake
    # the user's sources are compiled where they live: every .cpp below src/<package>
    assert 'set(ROBMOSYS_USER_CODE "${ROBMOSYS_SOURCE_DIR}/src/cpp_subscriber")' in cmake
    assert 'file(GLOB_RECURSE _user_sources CONFIGURE_DEPENDS ' \
        '"${ROBMOSYS_USER_CODE}/*.cpp")' in cmake
    assert 'rclcpp_components_register_nodes(${PROJECT_NAME}_component ' \
        '"cpp_subscriber::Subscriber_impl")' in cmake
    # the node is compiled once, in the library: its registration and its process
    # (run_Subscriber) with it, and a main that includes nothing, linked with it
    src = generated_cpp / 'cpp_subscriber' / 'src-gen' / 'cpp_subscriber'
    node = (src / 'Subscriber.cpp').read_text()
    assert 'RCLCPP_COMPONENTS_REGISTER_NODE(cpp_subscriber::Subscriber_impl)' in node
    assert 'robmosys_runtime::run<Subscriber_impl>(' in node
    main = (src / 'Subscriber_main.cpp').read_text()
    assert '#include' not in main and 'return cpp_subscriber::run_Subscriber(argc, argv);' in main
    assert 'add_executable(Subscriber src-gen/cpp_subscriber/Subscriber_main.cpp)\n' \
        'target_link_libraries(Subscriber ${PROJECT_NAME}_component)' in cmake
    assert cmake.count('src-gen/cpp_subscriber/Subscriber.cpp') == 1


def _cpp_files(root: Path) -> list[Path]:
    return sorted(p for p in root.rglob('*') if p.suffix in ('.cpp', '.hpp'))


def _linter_env() -> dict[str, str]:
    # the uncrustify binary of ros-uncrustify-vendor lives in opt/, off PATH
    env = dict(os.environ)
    env['PATH'] = os.pathsep.join([
        str(Path(sys.prefix) / 'opt' / 'uncrustify_vendor' / 'bin'),
        str(Path(sys.prefix) / 'bin'), env.get('PATH', '')])
    return env


def _linter(name: str) -> str:
    path = shutil.which(name, path=str(Path(sys.prefix) / 'bin'))
    if path is None:
        pytest.skip(f'{name} is not installed (ros-{name.replace("_", "-")} on PyPI)')
    return path


@pytest.mark.parametrize('linter', ['ament_cpplint', 'ament_uncrustify'])
def test_ament_cpp_linters_pass(generated_cpp, linter):
    """Every generated C++ file, skeletons and the example's own files included."""
    files = _cpp_files(generated_cpp)
    assert len(files) >= 9 * 5
    result = subprocess.run([_linter(linter), *map(str, files)], capture_output=True,
                            text=True, timeout=300, env=_linter_env())
    assert result.returncode == 0, result.stdout + result.stderr
    if linter == 'ament_uncrustify':
        assert 'No problems found' in result.stdout, result.stdout


def test_linters_are_not_blind(tmp_path):
    """The linter test would fail: a badly formatted header is caught by both."""
    bad = tmp_path / 'include' / 'bad' / 'bad.hpp'
    bad.parent.mkdir(parents=True)
    bad.write_text('#pragma once\nint f( int x ){return x;}\n')
    for linter in ('ament_cpplint', 'ament_uncrustify'):
        result = subprocess.run([_linter(linter), str(bad)], capture_output=True,
                                text=True, timeout=60, env=_linter_env())
        assert result.returncode != 0, linter


def _component_src(tmp_path: Path) -> Path:
    src = tmp_path / 'src'
    shutil.copytree(TEST_WORKSPACE / 'src', src)
    return src


def test_user_files_created_once_and_never_overwritten(tmp_path):
    src = _component_src(tmp_path)
    impl = src / 'cpp_subscriber' / 'src' / 'cpp_subscriber'
    before = {p.name: p.read_bytes() for p in impl.iterdir()}
    for path in impl.iterdir():
        path.unlink()
    plan = plan_package(_load(src), 'cpp_subscriber')
    created = create_missing_user_files(plan)
    assert sorted(p.name for p in created) == ['Subscriber_impl.cpp', 'Subscriber_impl.hpp']
    skeleton = impl / 'Subscriber_impl.hpp'
    assert 'class Subscriber_impl : public Subscriber' in skeleton.read_text()
    # the user's own version, then a regeneration: it stays as it is
    for name, data in before.items():
        (impl / name).write_bytes(data)
    assert create_missing_user_files(plan) == []
    report = generate_package(plan, tmp_path / 'out')
    assert {p.name: p.read_bytes() for p in impl.iterdir()} == before
    copied = tmp_path / 'out' / 'src' / 'cpp_subscriber' / 'Subscriber_impl.cpp'
    assert copied.read_bytes() == before['Subscriber_impl.cpp']
    assert copied in report.written


def test_missing_user_file_fails_with_the_command_to_create_it(tmp_path):
    src = _component_src(tmp_path)
    (src / 'cpp_server' / 'src' / 'cpp_server' / 'Server_impl.cpp').unlink()
    with pytest.raises(RobmosysError) as error:
        generate_package(plan_package(_load(src), 'cpp_server'), tmp_path / 'out')
    message = str(error.value)
    assert 'Server_impl.cpp: error: the implementation file is missing' in message
    assert 'colcon robmosys-generate --packages-select cpp_server' in message
    assert not (tmp_path / 'out').exists()


def test_function_the_user_lacks_is_named(tmp_path):
    src = _component_src(tmp_path)
    model = src / 'cpp_server' / 'robmosys.yaml'
    model.write_text(model.read_text().replace(
        '      Answer:\n', '      Tick: {period: 1.0, functions: [fTick]}\n      Answer:\n'
    ).replace('    functions:\n', '    functions:\n      fTick:\n'))
    header = src / 'cpp_server' / 'src' / 'cpp_server' / 'Server_impl.hpp'
    with pytest.raises(RobmosysError) as error:
        generate_package(plan_package(_load(src), 'cpp_server'), tmp_path / 'out')
    assert str(error.value) == (
        f"{header}:17:1: error: class 'Server_impl' lacks the function 'fTick' of "
        'the model; the skeleton src-skel/cpp_server/Server_impl.hpp of the package '
        'shows what the model asks for: '
        f"{tmp_path / 'out' / 'src-skel' / 'cpp_server' / 'Server_impl.hpp'}")


def test_function_named_only_in_a_comment_does_not_count(tmp_path):
    src = _component_src(tmp_path)
    header = src / 'cpp_receiver' / 'src' / 'cpp_receiver' / 'Receiver_impl.hpp'
    text = header.read_text()
    header.write_text(text.replace('  void fReceiving(', '  // void fReceiving(\n  void other('))
    with pytest.raises(RobmosysError, match="lacks the function 'fReceiving'"):
        generate_package(plan_package(_load(src), 'cpp_receiver'), tmp_path / 'out')


@pytest.mark.parametrize('text', [
    'plain', 'quote " and backslash \\', 'new\nline\ttab', '"); system("rm -rf /");',
    'trigraph ??/ and ??=', 'unicode é ✓', '*/ /* // \\',
])
def test_cpp_string_literals_keep_text_as_data(text):
    literal = cpp_str(text)
    assert literal.isascii() and '\n' not in literal
    assert _decode(literal) == text
    assert '??' not in literal


def test_cpp_comments_cannot_swallow_code():
    assert cpp_comment('first\nsecond \\') == '// first\n// second \\.'
    assert cpp_comment('text', '///') == '/// text'


def _decode(literal: str) -> str:
    """Read back a literal cpp_str wrote (only its escapes occur)."""
    body, out, i = literal[1:-1], bytearray(), 0
    while i < len(body):
        if body[i] == '\\':
            if body[i + 1].isdigit():
                out.append(int(body[i + 1:i + 4], 8))
                i += 4
                continue
            out += {'n': b'\n', 't': b'\t', 'r': b'\r', '\\': b'\\', '"': b'"',
                    '?': b'?'}[body[i + 1]]
            i += 2
            continue
        out += body[i].encode()
        i += 1
    return out.decode('utf-8')


def test_long_strings_are_split_into_lines_cpplint_accepts():
    text = 'é "quoted" \\ ' * 40
    lines = string_lines('descriptor.description', text)
    assert lines[0] == 'descriptor.description ='
    assert all(len('    ' + line) <= 100 for line in lines)
    assert lines[-1].endswith(';')
    literals = [line.strip().rstrip(';') for line in lines[1:]]
    assert ''.join(_decode(literal) for literal in literals) == text
    assert string_lines('x', 'short') == ['x = "short";']


def test_package_xml_is_valid_and_complete(generated_cpp):
    from catkin_pkg.package import parse_package
    for package in CPP_PACKAGES:
        parsed = parse_package(generated_cpp / package / 'package.xml')
        parsed.validate()
        depends = {d.name for d in parsed.build_depends} & {d.name for d in parsed.exec_depends}
        assert {'rclcpp', 'rclcpp_lifecycle', 'rclcpp_components', 'rcl_interfaces',
                'lifecycle_msgs'} <= depends, package
    depends = {d.name for d in parse_package(
        generated_cpp / 'all_ports' / 'package.xml').build_depends}
    assert {'rclcpp_action', 'all_ports_msgs'} <= depends


def test_rclcpp_is_looked_up_where_find_package_looks(tmp_path):
    """The ament index of a prefix, or a CMake config file, counts as installed."""
    from colcon_robmosys.package_selection.robmosys import missing_prefix_packages
    ament, cmake, workspace = tmp_path / 'ament', tmp_path / 'cmake', tmp_path / 'ws'
    (ament / 'share' / 'ament_index' / 'resource_index' / 'packages').mkdir(parents=True)
    (ament / 'share' / 'ament_index' / 'resource_index' / 'packages' / 'rclcpp').touch()
    (cmake / 'share' / 'rclcpp_lifecycle' / 'cmake').mkdir(parents=True)
    (cmake / 'share' / 'rclcpp_lifecycle' / 'cmake' / 'rclcpp_lifecycleConfig.cmake').touch()
    (workspace / 'share' / 'rclcpp_components' / 'cmake').mkdir(parents=True)
    (workspace / 'share' / 'rclcpp_components' / 'cmake' /
     'rclcpp_components-config.cmake').touch()
    names = ['rclcpp', 'rclcpp_lifecycle', 'rclcpp_components']
    environ = {'AMENT_PREFIX_PATH': str(ament), 'CMAKE_PREFIX_PATH': str(cmake)}
    assert missing_prefix_packages(names, [], environ=environ) == ['rclcpp_components']
    assert missing_prefix_packages(names, [str(workspace)], environ=environ) == []
    assert missing_prefix_packages(names, [], environ={}) == names
