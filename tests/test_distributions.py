# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""The shell's ROS_DISTRO: supported ones build, older ones are refused first.

The generated code is the same for Jazzy and Kilted (docs/distributions.md);
a shell of an older distribution gets one error line from ``colcon build``,
before anything is generated, instead of a compiler's or rclpy's error deep
in some package, and a warning from ``colcon robmosys-generate``.
"""

from __future__ import annotations

from pathlib import Path
import shutil

import pytest

from colcon_robmosys.mapping.distributions import distribution_problem, SUPPORTED
from conftest import colcon, requires_ros, TEST_WORKSPACE

#: the shell of an older distribution
HUMBLE = {'ROS_DISTRO': 'humble'}


@pytest.mark.parametrize('value', ['', 'jazzy', 'kilted', 'rolling', 'lyrical', 'Jazzy'])
def test_supported_and_unknown_distributions_pass(value):
    assert distribution_problem({'ROS_DISTRO': value}) is None
    assert distribution_problem({}) is None


@pytest.mark.parametrize('value', ['humble', 'iron', 'foxy', ' Humble\n'])
def test_older_distributions_are_refused_with_the_reason(value):
    problem = distribution_problem({'ROS_DISTRO': value})
    assert problem is not None
    name = value.strip().lower()
    assert problem.startswith(f"ROS_DISTRO is '{name}': the generated code needs ROS 2 "
                              'Jazzy or newer (')


def test_the_documented_distributions_are_the_supported_ones():
    docs = (Path(__file__).resolve().parent.parent / 'docs' / 'distributions.md').read_text()
    assert all(f'**{name.capitalize()}**' in docs for name in SUPPORTED)


@requires_ros
@pytest.mark.integration
def test_build_on_an_older_distribution_is_one_error_and_nothing_generated(tmp_path):
    shutil.copytree(TEST_WORKSPACE / 'src', tmp_path / 'src',
                    ignore=shutil.ignore_patterns('__pycache__'))
    before = sorted(p.relative_to(tmp_path) for p in (tmp_path / 'src').rglob('*'))
    result = colcon(['build', '--packages-select', 'sender', 'receiver'], cwd=tmp_path,
                    extra_env=HUMBLE)
    assert result.returncode != 0, result.stdout + result.stderr
    errors = [line for line in result.stderr.splitlines() if line.startswith('error: ')]
    assert errors == [f'error: {distribution_problem(HUMBLE)}'], \
        result.stderr
    assert "cannot generate 'sender': see the error on ROS_DISTRO" in result.stderr
    assert "cannot generate 'receiver': see the error on ROS_DISTRO" in result.stderr
    assert not list((tmp_path / 'build').glob('*/src-gen'))
    # the user's files: none written, none changed
    assert sorted(p.relative_to(tmp_path) for p in (tmp_path / 'src').rglob('*')) == before


@requires_ros
@pytest.mark.integration
def test_generate_on_an_older_distribution_warns_and_generates(tmp_path):
    shutil.copytree(TEST_WORKSPACE / 'src', tmp_path / 'src',
                    ignore=shutil.ignore_patterns('__pycache__'))
    out = tmp_path / 'generated'
    result = colcon(['robmosys-generate', '--packages-select', 'sender',
                     '--output-dir', str(out)], cwd=tmp_path, extra_env=HUMBLE)
    assert result.returncode == 0, result.stdout + result.stderr
    assert f'warning: {distribution_problem(HUMBLE)}' in \
        result.stderr.splitlines()
    assert (out / 'sender' / 'package.xml').is_file()
