# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""Our own code meets the style we ask of generated code (flake8, as colcon does).

mypy checks the type hints the house style asks for.
"""

from __future__ import annotations

import os
from pathlib import Path
import subprocess
import sys

import pytest

REPO = Path(__file__).resolve().parent.parent


def test_flake8():
    pytest.importorskip('flake8', reason='flake8 is installed by `make test`')
    result = subprocess.run(
        [sys.executable, '-m', 'flake8', '--config', str(REPO / 'setup.cfg'),
         'colcon_robmosys', 'tests', 'tools', 'bench'],
        cwd=REPO, capture_output=True, text=True, timeout=300)
    assert result.returncode == 0, result.stdout + result.stderr


def test_mypy():
    pytest.importorskip('mypy', reason='mypy is installed by `make test`')
    result = subprocess.run(
        [sys.executable, '-m', 'mypy', '--config-file', str(REPO / 'setup.cfg'),
         '--cache-dir', os.devnull, 'colcon_robmosys', 'bench'],
        cwd=REPO, capture_output=True, text=True, timeout=300,
        env={**os.environ, 'MYPYPATH': str(REPO / 'tests')})
    assert result.returncode == 0, result.stdout + result.stderr


def test_mypy_strict_on_the_core():
    """The layers under the generators pass mypy --strict, whatever setup.cfg says."""
    pytest.importorskip('mypy', reason='mypy is installed by `make test`')
    result = subprocess.run(
        [sys.executable, '-m', 'mypy', '--config-file', str(REPO / 'setup.cfg'),
         '--cache-dir', os.devnull, '--strict', '-p', 'colcon_robmosys.model',
         '-p', 'colcon_robmosys.check', '-p', 'colcon_robmosys.mapping',
         '-p', 'colcon_robmosys.report'],
        cwd=REPO, capture_output=True, text=True, timeout=300)
    assert result.returncode == 0, result.stdout + result.stderr
