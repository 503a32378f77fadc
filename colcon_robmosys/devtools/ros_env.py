# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""
The environment in which tests, demos and benchmarks run ROS 2 and colcon.

The venv that runs the tests is the ROS 2 prefix (PyPI's ``ros-*`` wheels, fixed up by
``tools/bootstrap_ros_wheels.py``). Every DDS participant stays on loopback through
``fastdds_loopback.xml`` (next to this module), and every test gets its own ``ROS_DOMAIN_ID``.
Every process started here has a timeout, and is killed with its children.
"""

from __future__ import annotations

from collections.abc import Iterator, Mapping, Sequence
import contextlib
import fcntl
import itertools
import os
from pathlib import Path
import signal
import socket
import subprocess
import sys
import tempfile
from typing import Any, IO

Command = Sequence[str | os.PathLike[str]]

FASTDDS_PROFILE: Path = Path(__file__).resolve().parent / 'fastdds_loopback.xml'
#: ``ROS_AUTOMATIC_DISCOVERY_RANGE`` of every process here: the profile alone keeps DDS
#: on loopback. ``LOCALHOST`` would not: rmw_fastrtps (Jazzy and Kilted) then adds a
#: shared memory transport and a UDPv4 transport on every interface to the profile's,
#: so a process binds 0.0.0.0 and the machine's own addresses, and the shared memory
#: that processes killed on purpose leave in /dev/shm can crash a later one (the
#: profile says more). ``SYSTEM_DEFAULT`` leaves the participant as the profile made it.
DISCOVERY_RANGE = 'SYSTEM_DEFAULT'

# Variables that would widen discovery beyond this machine or replace our profile.
_NON_LOCAL = (
    'ROS_LOCALHOST_ONLY',  # deprecated; conflicts with ROS_AUTOMATIC_DISCOVERY_RANGE
    'ROS_STATIC_PEERS',
    'ROS_DISCOVERY_SERVER',
    'FASTRTPS_DEFAULT_PROFILES_FILE',  # the Fast DDS 2 name of the profile variable
    'FASTDDS_ENVIRONMENT_FILE',
)

# ROS 2 documents 0..101 as the domain ids whose ports stay clear of Linux's
# ephemeral port range; 0 is everyone's default, so tests avoid it.
_DOMAIN_IDS = 101
#: how many of them one process holds at most
_HELD_DOMAIN_IDS = 16
_domain_counter = itertools.count()
_domain_locks: dict[int, tuple[IO[str], socket.socket]] = {}
#: ROS 2's own test isolation holds a domain id by binding this port plus the id:
#: ament_cmake_ros's run_rmw_isolated (Kilted's rmw_test_fixture, 127.0.0.1) and
#: domain_coordinator (Jazzy, every address); `colcon test` of a generated smoke test
#: runs under it, with an id of its choosing in 1..100, whatever ROS_DOMAIN_ID says
_ISOLATION_PORT_BASE = 32768


def ros_prefix() -> Path:
    """Return the ROS 2 prefix: the venv of the running interpreter."""
    return Path(sys.prefix)


def _path_list(first: Sequence[Path | str], rest: str | None) -> str:
    """Join ``first`` and then the entries of ``rest`` into a path list, without duplicates."""
    entries = [str(p) for p in first] + (rest or '').split(os.pathsep)
    return os.pathsep.join(dict.fromkeys(e for e in entries if e))


def loopback_env(domain_id: int, base: Mapping[str, str] | None = None,
                 underlays: Sequence[Path] = ()) -> dict[str, str]:
    """
    Return a copy of ``base`` (default: ``os.environ``) that keeps ROS 2 on loopback.

    :param domain_id: the ``ROS_DOMAIN_ID``, see :func:`free_domain_id`
    :param underlays: prefixes searched before the ROS prefix, first one first
    """
    if not 0 <= domain_id <= 232:
        raise ValueError(f'ROS_DOMAIN_ID {domain_id} is out of range 0..232')
    # LD_LIBRARY_PATH and _ROS_WHEELS_BOOTSTRAP_COMPLETE pass through: a Python child
    # that finds the guard set skips the wheels' re-exec, which would reorder every
    # LD_LIBRARY_PATH entry at random (it goes through a set), overlays included.
    env = dict(os.environ if base is None else base)
    for name in _NON_LOCAL:
        env.pop(name, None)
    prefix = ros_prefix()
    # The ROS prefix goes before what the caller had: a ROS install sourced in
    # the caller's shell must not shadow the venv, but may add what it lacks.
    for name in ('CMAKE_PREFIX_PATH', 'AMENT_PREFIX_PATH'):
        env[name] = _path_list([*underlays, prefix], env.get(name))
    # Vendored tools (uncrustify for ament_uncrustify) live in opt/<vendor>/bin.
    env['PATH'] = _path_list([prefix / 'bin', *sorted(prefix.glob('opt/*/bin'))], env.get('PATH'))
    env.update({
        'FASTDDS_DEFAULT_PROFILES_FILE': str(FASTDDS_PROFILE),
        'RMW_IMPLEMENTATION': 'rmw_fastrtps_cpp',
        'ROS_AUTOMATIC_DISCOVERY_RANGE': DISCOVERY_RANGE,
        'ROS_DOMAIN_ID': str(domain_id),
        'PYTHONUNBUFFERED': '1',
        'RCUTILS_COLORIZED_OUTPUT': '0',
    })
    return env


def workspace_env(install_dir: Path, env: Mapping[str, str]) -> dict[str, str]:
    """
    Return ``env`` after sourcing ``install_dir/local_setup.sh`` with ``sh``.

    Sourcing the script is what a user does, so the test sees what the user sees,
    hooks (``.dsv``/``.sh``) included. ``COLCON_CURRENT_PREFIX`` makes a moved install
    work. Raises :class:`RuntimeError` with the script's output if sourcing fails.
    """
    install_dir = Path(install_dir).resolve()
    script = install_dir / 'local_setup.sh'
    if not script.is_file():
        raise FileNotFoundError(script)
    env_in = dict(env, COLCON_CURRENT_PREFIX=str(install_dir))
    result = run(['sh', '-c', '. "$1" && env -0', 'sh', str(script)],
                 env=env_in, timeout=60, binary=True)
    if result.returncode != 0:
        raise RuntimeError(f'sourcing {script} failed ({result.returncode}):\n'
                           + result.stderr.decode(errors='replace'))
    out: dict[str, str] = {}
    for item in result.stdout.decode().split('\0'):
        name, sep, value = item.partition('=')
        if sep:
            out[name] = value
    # Drop what the shell itself adds; keep the caller's values for the rest.
    for name in ('_', 'SHLVL', 'PWD', 'OLDPWD', 'COLCON_CURRENT_PREFIX'):
        out.pop(name, None)
        if name in env:
            out[name] = env[name]
    return out


def free_domain_id() -> int:
    """
    Return a ``ROS_DOMAIN_ID`` in 1..101 that no other live process here holds.

    The sequence starts at an offset taken from the pid and steps by a counter, so
    concurrent pytest processes start apart; a lock file per id (held until this
    process exits) makes sure they never share one. The id is held the way ROS 2's
    test isolation holds one too, by its port (``_ISOLATION_PORT_BASE``): a smoke
    test under `colcon test` in another test never lands in a domain a test here
    runs a system in (CI saw one manager take the other's nodes down). A process
    holds at most 16 ids and then reuses its own in turn, which is safe because
    its earlier tests stopped their processes, and leaves the others to other
    processes.
    """
    lock_dir = Path(tempfile.gettempdir()) / 'colcon-robmosys-domain-ids'
    lock_dir.mkdir(exist_ok=True)
    if len(_domain_locks) >= _HELD_DOMAIN_IDS:
        held = sorted(_domain_locks)
        return held[next(_domain_counter) % len(held)]
    offset = os.getpid() * 37  # 37: consecutive pids start far apart
    for _ in range(_DOMAIN_IDS):
        domain_id = 1 + (offset + next(_domain_counter)) % _DOMAIN_IDS
        if domain_id in _domain_locks:
            return domain_id
        handle = open(lock_dir / f'{domain_id}.lock', 'a')
        try:
            fcntl.flock(handle, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError:
            handle.close()
            continue
        port = socket.socket(socket.AF_INET, socket.SOCK_STREAM)
        try:
            # every address: it excludes a bind of 127.0.0.1 and one of all
            port.bind(('', _ISOLATION_PORT_BASE + domain_id))
        except OSError:
            port.close()
            handle.close()
            continue
        _domain_locks[domain_id] = (handle, port)
        return domain_id
    raise RuntimeError(f'all ROS domain ids 1..{_DOMAIN_IDS} are held by other processes')


def _kill_group(proc: subprocess.Popen[Any]) -> None:
    """Kill ``proc`` and everything it started (it leads its own session)."""
    with contextlib.suppress(ProcessLookupError):
        os.killpg(proc.pid, signal.SIGKILL)


def run(cmd: Command, *, env: Mapping[str, str], timeout: float,
        cwd: Path | str | None = None, binary: bool = False) -> subprocess.CompletedProcess[Any]:
    """
    Run ``cmd`` to completion and capture its output (text unless ``binary``).

    On timeout the command and all its children are killed and
    :class:`subprocess.TimeoutExpired` is raised with the output so far.
    """
    with subprocess.Popen(cmd, env=dict(env), cwd=cwd, text=not binary,
                          stdin=subprocess.DEVNULL, stdout=subprocess.PIPE,
                          stderr=subprocess.PIPE, start_new_session=True) as proc:
        try:
            stdout, stderr = proc.communicate(timeout=timeout)
        except subprocess.TimeoutExpired:
            _kill_group(proc)
            stdout, stderr = proc.communicate()
            raise subprocess.TimeoutExpired(proc.args, timeout, stdout, stderr) from None
        except BaseException:  # noqa: B902 - never leave the process group behind
            _kill_group(proc)
            raise
    return subprocess.CompletedProcess(proc.args, proc.returncode, stdout, stderr)


class Background:
    """A process started by :func:`background`; stdout and stderr go to one file."""

    def __init__(self, proc: subprocess.Popen[Any], log: IO[bytes]) -> None:
        self.proc = proc
        self._log = log

    def output(self) -> str:
        """Return everything the process printed so far."""
        # pread: the child shares the file offset, so seeking would misplace its writes.
        fd = self._log.fileno()
        return os.pread(fd, os.fstat(fd).st_size, 0).decode(errors='replace')


@contextlib.contextmanager
def background(cmd: Command, *, env: Mapping[str, str], stop_timeout: float = 5.0,
               cwd: Path | str | None = None) -> Iterator[Background]:
    """
    Start ``cmd`` for the duration of a ``with`` block, then stop it and its children.

    On exit it gets SIGINT (a ROS node shuts down cleanly), then SIGKILL after
    ``stop_timeout`` seconds. Output goes to a file, so a chatty process never blocks.

    A Python process that does not end on SIGINT says where it hung: it runs with
    :mod:`faulthandler` on and gets SIGABRT before SIGKILL, and what it printed
    then goes to this process's stderr (which pytest shows with a failure).
    """
    command = [str(part) for part in cmd]
    python = Path(command[0]).name.startswith('python') or command[0] == sys.executable
    env = {**env, 'PYTHONFAULTHANDLER': '1'} if python else dict(env)
    with tempfile.TemporaryFile() as log:
        proc = subprocess.Popen(cmd, env=env, cwd=cwd, text=True,
                                stdin=subprocess.DEVNULL, stdout=log,
                                stderr=subprocess.STDOUT, start_new_session=True)
        process = Background(proc, log)
        try:
            yield process
        finally:
            with contextlib.suppress(ProcessLookupError):
                os.killpg(proc.pid, signal.SIGINT)
            try:
                proc.wait(timeout=stop_timeout)
            except subprocess.TimeoutExpired:
                _say_where_it_hung(' '.join(command), process, stop_timeout, python)
            _kill_group(proc)  # children may outlive a leader that exited
            proc.wait()


def _say_where_it_hung(command: str, process: Background, stop_timeout: float,
                       python: bool) -> None:
    """Print to stderr that a process did not end on SIGINT, with its stacks if Python's."""
    proc = process.proc
    before = len(process.output())
    if python:
        with contextlib.suppress(ProcessLookupError):
            os.kill(proc.pid, signal.SIGABRT)  # faulthandler prints every thread's stack
        with contextlib.suppress(subprocess.TimeoutExpired):
            proc.wait(timeout=5)
    command = command.replace('\n', ' ')
    print(f'{command[:120]}: did not end within {stop_timeout:g} s of SIGINT; killed. '
          f'What it printed then:\n{process.output()[before:][-8000:]}', file=sys.stderr)
