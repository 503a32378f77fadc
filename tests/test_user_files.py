# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""The user's own files of a Python component: built, installed and tested where they live.

Extra modules, a config file and pytest tests next to the model (docs/model-format.md,
"Your own files"), on a real `colcon build` and `colcon test`.
"""

from __future__ import annotations

import json
from pathlib import Path
import shutil
import xml.etree.ElementTree as ET

import pytest
# the same component: its model, and how to see its node run
from test_user_code import assert_echo_logs, MODEL

from conftest import colcon, requires_ros

pytestmark = [pytest.mark.integration, requires_ros]

IMPL = '''\
"""The user's implementation of Echo."""

from echo.Echo import Echo
from echo.text.words import greeting
from std_msgs.msg import String


class Echo_impl(Echo):
    """Publish what the helper module says."""

    def fTick(self) -> None:
        """Publish a text."""
        self.pOut.publish(String(data=greeting()))
        self.get_logger().info(greeting())
'''

#: a subpackage of the user's, with a flake8 finding (F401) on its line 3
WORDS = '''\
"""Words of the user's own module."""

import os


def greeting() -> str:
    """Return the text the node publishes."""
    return 'hello from words'
'''

USER_TESTS = '''\
"""The user's tests, on the installed package."""

from echo.text.words import greeting


def test_greeting():
    """Pass: the module is importable."""
    assert greeting() == 'hello from words'


def test_fails():
    """Fail on purpose."""
    assert greeting() == 'something else'
'''


def _ok(result) -> None:
    assert result.returncode == 0, result.stdout + result.stderr


def _workspace(root: Path) -> Path:
    """Write the component and the user's files into root/src/echo."""
    package = root / 'src' / 'echo'
    files = {
        'robmosys.yaml': MODEL,
        'src/echo/Echo_impl.py': IMPL,
        'src/echo/text/__init__.py': '"""Texts."""\n',
        'src/echo/text/words.py': WORDS,
        'config/echo.yaml': 'echo:\n  ros__parameters: {}\n',
        'test/test_words.py': USER_TESTS,
    }
    for relative, text in files.items():
        (package / relative).parent.mkdir(parents=True, exist_ok=True)
        (package / relative).write_text(text)
    return package


def _test_cases(results: Path) -> dict[str, str]:
    """Return each test case of a JUnit file -> 'passed' or 'failed'."""
    cases = {}
    for case in ET.parse(results).getroot().iter('testcase'):
        failed = case.find('failure') is not None or case.find('error') is not None
        cases[case.get('name')] = 'failed' if failed else 'passed'
    return cases


def test_user_files_are_built_installed_and_tested(tmp_path, domain_id):
    package = _workspace(tmp_path)
    _ok(colcon(['build', '--event-handlers', 'console_cohesion+'], cwd=tmp_path))
    install = tmp_path / 'install'
    site = next((install / 'echo').rglob('site-packages/echo'))
    assert (site / 'text' / 'words.py').read_text() == WORDS
    assert (install / 'echo' / 'share' / 'echo' / 'config' / 'echo.yaml').is_file()
    # the build tree holds no copy of the user's files
    generated = tmp_path / 'build' / 'echo' / 'src-gen'
    assert not list(generated.rglob('words.py'))
    assert not list(generated.glob('echo/Echo_impl.py'))

    # the node imports the user's module and uses it
    assert_echo_logs(install, domain_id, 'hello from words')

    # colcon test runs the user's tests and reports the failing one; flake8
    # points at the user's file where it lives
    result = colcon(['test', '--event-handlers', 'console_cohesion+'], cwd=tmp_path,
                    timeout=600)
    output = result.stdout + result.stderr
    results = tmp_path / 'build' / 'echo' / 'test_results' / 'echo'
    assert _test_cases(results / 'user_pytest.xunit.xml') == {
        'test_greeting': 'passed', 'test_fails': 'failed'}, output
    words = package / 'src' / 'echo' / 'text' / 'words.py'
    assert f'F401 ({words}:3:1)' in (results / 'flake8.xunit.xml').read_text()
    summary = colcon(['test-result'], cwd=tmp_path, timeout=60)
    assert summary.returncode != 0
    assert 'user_pytest' in summary.stdout, summary.stdout


def test_symlink_install_links_the_user_files_to_the_source(tmp_path):
    package = _workspace(tmp_path)
    _ok(colcon(['build', '--symlink-install'], cwd=tmp_path))
    install = tmp_path / 'install' / 'echo'
    site = next(install.rglob('site-packages/echo'))
    for installed, source in (
            (site / 'Echo_impl.py', package / 'src' / 'echo' / 'Echo_impl.py'),
            (site / 'text' / 'words.py', package / 'src' / 'echo' / 'text' / 'words.py'),
            (install / 'share' / 'echo' / 'config' / 'echo.yaml',
             package / 'config' / 'echo.yaml')):
        assert installed.is_symlink(), installed
        assert installed.resolve() == source.resolve()
    # an edit needs no rebuild
    (package / 'src' / 'echo' / 'text' / 'words.py').write_text(
        WORDS.replace('hello from words', 'edited'))
    assert 'edited' in (site / 'text' / 'words.py').read_text()


#: a helper next to the C++ implementation file, and an extra source
WORDS_HPP = """\
// A helper of the user's, next to the implementation file.
#ifndef CPP_RECEIVER__WORDS_HPP_
#define CPP_RECEIVER__WORDS_HPP_

#include <string>

namespace cpp_receiver
{
std::string words();
}  // namespace cpp_receiver

#endif  // CPP_RECEIVER__WORDS_HPP_
"""
WORDS_CPP = """\
// An extra source of the user's: compiled into the component's library.
#include "cpp_receiver/words.hpp"

#include <string>

namespace cpp_receiver
{
std::string words() {return "words of the user";}
}  // namespace cpp_receiver
"""
GTEST = """\
// The user's gtest, linked with the component's library.
#include <gtest/gtest.h>

#include "cpp_receiver/words.hpp"

TEST(Words, AreTheUsers) {EXPECT_EQ(cpp_receiver::words(), "words of the user");}
"""


def test_cpp_user_files_compile_where_they_live_and_their_gtest_runs(tmp_path):
    from test_cpp_system import rclcpp_missing_reason
    if rclcpp_missing_reason():
        pytest.skip(rclcpp_missing_reason())
    from conftest import TEST_WORKSPACE
    src = tmp_path / 'src'
    for package in ('simple_msgs', 'cpp_receiver'):
        shutil.copytree(TEST_WORKSPACE / 'src' / package, src / package)
    code = src / 'cpp_receiver' / 'src' / 'cpp_receiver'
    (code / 'words.hpp').write_text(WORDS_HPP)
    (code / 'words.cpp').write_text(WORDS_CPP)
    impl = code / 'Receiver_impl.cpp'
    text = impl.read_text().replace(
        '#include <memory>\n', '#include <memory>\n\n#include "cpp_receiver/words.hpp"\n')
    impl.write_text(text.replace('"received map: width %u, height %u", ',
                                 '"%s: width %u, height %u", words().c_str(), '))
    (src / 'cpp_receiver' / 'test').mkdir()
    (src / 'cpp_receiver' / 'test' / 'words_test.cpp').write_text(GTEST)
    (src / 'cpp_receiver' / 'config').mkdir()
    (src / 'cpp_receiver' / 'config' / 'extra.yaml').write_text('a: 1\n')
    _ok(colcon(['build', '--cmake-args', '-DCMAKE_EXPORT_COMPILE_COMMANDS=ON'],
               cwd=tmp_path, timeout=1200))
    # compiled where they live: compilers and tools name the user's files
    commands = json.loads((tmp_path / 'build' / 'cpp_receiver' /
                           'compile_commands.json').read_text())
    files = {Path(c['file']).resolve() for c in commands}
    assert {impl.resolve(), (code / 'words.cpp').resolve()} <= files, files
    assert (tmp_path / 'install' / 'cpp_receiver' / 'share' / 'cpp_receiver' / 'config' /
            'extra.yaml').is_file()
    _ok(colcon(['test', '--packages-select', 'cpp_receiver', '--ctest-args', '-R', 'user'],
               cwd=tmp_path, timeout=600))
    cases: dict[str, str] = {}
    for results in (tmp_path / 'build' / 'cpp_receiver' / 'test_results').rglob('*.xml'):
        cases.update(_test_cases(results))
    assert cases.get('AreTheUsers') == 'passed', cases
