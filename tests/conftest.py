# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""Fixtures shared by the tests: the ROS environment and the built test workspace."""

from __future__ import annotations

from dataclasses import dataclass, field
import fcntl
import os
from pathlib import Path
import pickle
import shutil
import sys
from typing import Iterator

import pytest

from colcon_robmosys.devtools import netns, ros_env, workspace

REPO = Path(__file__).resolve().parent.parent
TEST_WORKSPACE = REPO / 'test_workspace'


def ros_missing_reason() -> str | None:
    """Return why real ROS 2 cannot run here, or None if it can."""
    try:
        import rclpy  # noqa: F401
    except ImportError as error:
        return f'rclpy is not importable ({error}): run the tests with `make test`'
    if shutil.which('colcon', path=str(Path(sys.prefix) / 'bin')) is None:
        return 'colcon is not installed in this venv: run the tests with `make test`'
    return None


requires_ros = pytest.mark.skipif(ros_missing_reason() is not None,
                                  reason=ros_missing_reason() or '')


@dataclass(frozen=True)
class BuiltWorkspace:
    """A workspace built with colcon."""

    root: Path
    build_output: str
    bases: workspace.Bases = field(default_factory=workspace.Bases)
    #: where this build came after an earlier one of the same folders (the demo's, in
    #: CI): the mtime of each file of build and install before it and after it
    rebuilt: tuple[dict[str, int], dict[str, int]] | None = None

    @property
    def install(self) -> Path:
        """Return the install folder."""
        return self.root / self.bases.install

    @property
    def build(self) -> Path:
        """Return the build folder."""
        return self.root / self.bases.build

    def colcon(self, verb: str, *args: str, timeout: float = 900):
        """Run a colcon verb on this workspace's own folders."""
        return colcon(self.bases.command(verb, *args), cwd=self.root, timeout=timeout)

    def env(self, domain_id: int) -> dict[str, str]:
        """Return the environment of a user who sourced the install, on loopback."""
        return ros_env.workspace_env(self.install, ros_env.loopback_env(domain_id))

    def share(self, package: str) -> Path:
        """Return the installed share folder of a package."""
        return self.install / package / 'share' / package


def colcon(args: list[str], *, cwd: Path, timeout: float = 900, domain_id: int = 0,
           extra_env: dict[str, str] | None = None) -> 'ros_env.subprocess.CompletedProcess':
    """Run colcon from this venv in a workspace, on loopback (plus ``extra_env``)."""
    env = ros_env.loopback_env(domain_id or ros_env.free_domain_id())
    env.update(extra_env or {})
    return ros_env.run([str(Path(sys.prefix) / 'bin' / 'colcon'), *args],
                       env=env, cwd=cwd, timeout=timeout)


def hosts_of(names: tuple[str, ...], tmp_path_factory: pytest.TempPathFactory) \
        -> Iterator[netns.Network]:
    """
    Yield hosts of names as network namespaces, for a fixture of a module.

    They are removed after it; a test that needs them is skipped with the
    reason where they cannot be made (not Linux, not root, no iproute2).
    """
    reason = netns.unavailable_reason()
    if reason:
        pytest.skip(reason)
    with netns.Network(names, tmp_path_factory.mktemp('hosts')) as network:
        yield network


def build_workspace(src: Path, root: Path, *extra: str) -> BuiltWorkspace:
    """Copy a workspace's src folder to root and build it with colcon."""
    shutil.copytree(src, root / 'src', ignore=shutil.ignore_patterns('__pycache__'))
    result = colcon(['build', '--event-handlers', 'console_cohesion+', *extra], cwd=root)
    output = result.stdout + result.stderr
    assert result.returncode == 0, f'colcon build failed:\n{output}'
    return BuiltWorkspace(root, output)


@pytest.fixture(scope='session')
def test_workspace_built(tmp_path_factory) -> BuiltWorkspace:
    """Return test_workspace, built once per test session.

    With the repository's own venv of its distribution, it is built in place, where
    ``make demo`` builds it (``workspace.bases_of``), so that after the demo (CI runs it
    first) this build finds nothing to do; a lock keeps two test sessions from
    building it at the same time. Any other venv (another prefix, with other
    packages and another Python) builds a copy of its own.
    """
    if ros_missing_reason():
        pytest.skip(ros_missing_reason())
    distribution = workspace.venv_distribution()
    if Path(sys.prefix).resolve() != (REPO / workspace.DEFAULT_VENVS[distribution]).resolve():
        return build_workspace(TEST_WORKSPACE / 'src', tmp_path_factory.mktemp('test_ws'))
    bases = workspace.bases_of(distribution)
    (TEST_WORKSPACE / bases.build).mkdir(exist_ok=True)
    # under pytest-xdist (make test), the workers of one run build it once: the first
    # to take the lock builds, the others read what it built (a build of the others
    # would rewrite what colcon rewrites on every build under the first one's nodes)
    run = os.environ.get('PYTEST_XDIST_TESTRUNUID')
    session = TEST_WORKSPACE / bases.build / '.tests-session.pickle'
    with open(TEST_WORKSPACE / bases.build / '.tests.lock', 'w') as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        if run and session.is_file():
            earlier_run, built = pickle.loads(session.read_bytes())
            if earlier_run == run:
                return built
        before = mtimes(TEST_WORKSPACE, bases.build, bases.install)
        result = colcon(bases.command('build', '--event-handlers', 'console_cohesion+'),
                        cwd=TEST_WORKSPACE)
        after = mtimes(TEST_WORKSPACE, bases.build, bases.install)
        output = result.stdout + result.stderr
        assert result.returncode == 0, f'colcon build failed:\n{output}'
        # a build over an earlier one: tests/test_rebuild.py reads what it rewrote
        earlier = any(n.startswith(f'{bases.install}/') for n in before)
        built = BuiltWorkspace(TEST_WORKSPACE, output, bases,
                               (before, after) if earlier else None)
        if run:
            session.write_bytes(pickle.dumps((run, built)))
    return built


def mtimes(root: Path, *bases: str) -> dict[str, int]:
    """Return the mtime of each file below the bases of root, by its path from root."""
    return {str(path.relative_to(root)): path.stat().st_mtime_ns
            for base in bases for path in (root / base).rglob('*')
            if path.is_file()}


def contents(root: Path, *bases: str) -> dict[str, bytes]:
    """Return the content of each file below the bases of root (all of it), by path from root."""
    return {path.relative_to(root).as_posix(): path.read_bytes()
            for base in bases or ('.',) for path in (root / base).rglob('*')
            if path.is_file()}


@pytest.fixture
def domain_id() -> int:
    """Return a ROS_DOMAIN_ID of this test's own."""
    return ros_env.free_domain_id()


def assert_no_traceback(output: str, everything: str = '') -> None:
    """
    Fail when output holds a Python traceback; the message starts with each one.

    What CI shows of a failure is its first lines: a traceback at the end of
    a long output, as the whole output is, never reached the log.
    """
    lines = output.splitlines()
    found = [i for i, line in enumerate(lines) if 'Traceback (most recent call last)' in line]
    excerpts = ['\n'.join(lines[i:i + 40]) for i in found]
    assert not found, '\n...\n'.join(excerpts) + f'\n--- the whole output:\n{everything or output}'


def pytest_terminal_summary(terminalreporter) -> None:
    """Print what tests measured (``record_property('measured', line)``), as a section.

    The figures of a test that asserts only that a system works (the fleet's
    link and CPU, tests/test_fleet.py) show in CI's log, with pytest-xdist too:
    a report's properties travel from the worker that ran it.
    """
    lines = [value for reports in terminalreporter.stats.values() for report in reports
             if getattr(report, 'when', None) == 'call'
             for name, value in getattr(report, 'user_properties', ()) if name == 'measured']
    if lines:
        terminalreporter.section('measured')
        for line in lines:
            terminalreporter.write_line(str(line))
