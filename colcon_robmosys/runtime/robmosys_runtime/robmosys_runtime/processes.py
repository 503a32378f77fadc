# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""
The processes of a system's instances: their command lines, grouped, watched.

One process per instance runs the instance's executable with the arguments
launch_ros would give it. With ``processes: shared`` the Python instances of
a host share one multi-threaded process (:mod:`robmosys_runtime.container`):
a 50-instance system then does not start 50 Python interpreters.
"""

from __future__ import annotations

import functools
import os
import signal
import subprocess
import sys
import threading
import time
from typing import Any, Callable, Dict, List, NamedTuple, Optional, Sequence, Set, Tuple

from ament_index_python.packages import get_package_prefix, PackageNotFoundError
from robmosys_runtime.output import say

#: seconds each process has to end after SIGINT, before SIGABRT and SIGKILL
STOP_TIMEOUT = 10.0
#: seconds a process that did not end of SIGINT has, after SIGABRT, to print
#: where its threads are (Python's faulthandler), before SIGKILL
ABORT_GRACE = 3.0


def command(instance: Dict[str, Any], params_file: str) -> List[str]:
    """Return the command line of an instance, as launch_ros would build it."""
    executable = instance.get('command') or [os.path.join(
        get_package_prefix(instance['package']), 'lib', instance['package'],
        instance['executable'])]
    args = list(executable) + ['--ros-args', '-r', f"__node:={instance['name']}"]
    if instance['namespace']:
        args += ['-r', f"__ns:={instance['namespace']}"]
    return args + node_arguments(instance, params_file)


def _ending_with_parent() -> Optional[Callable[[], None]]:
    """
    Return what a child calls to get SIGTERM when the thread that started it ends (Linux).

    prctl(PR_SET_PDEATHSIG): the instances of a host's ``bringup`` end with
    it, even when it is killed. Otherwise they would live on unsupervised,
    and the ``bringup`` started again would start a second node of each name.
    The function is looked up here, in the parent: the child only calls it.
    """
    if not sys.platform.startswith('linux'):
        return None
    import ctypes  # here: bringup starts the instances before anything else
    try:
        prctl = ctypes.CDLL(None, use_errno=True).prctl
    except (OSError, AttributeError):
        return None
    return functools.partial(prctl, _PR_SET_PDEATHSIG, int(signal.SIGTERM))


_PR_SET_PDEATHSIG = 1


class Processes:
    """
    The processes of the instances, watched: one that ends is reported.

    :param end_with_parent: whether each process gets SIGTERM when the thread
        that started it ends (start them from threads that live as long as
        the process, as a host's ``bringup`` does)
    """

    def __init__(self, on_exit: Any, end_with_parent: bool = False) -> None:
        self._preexec = _ending_with_parent() if end_with_parent else None
        self._processes: Dict[str, subprocess.Popen[bytes]] = {}
        #: called with (name, exit code) once a process ends, while watched
        self.on_exit = on_exit
        self._stopping = threading.Event()
        #: the processes asked to end already (interrupt): asked once only
        self._interrupted: Set[str] = set()
        self._watch = threading.Thread(target=self._watch_loop, daemon=True)

    def start(self, name: str, args: Sequence[str], pass_fds: Sequence[int] = ()) -> None:
        """
        Start an instance in a session of its own: a Ctrl-C reaches only bringup.

        :param pass_fds: file descriptors the process inherits (``--report-fd``)
        """
        self._processes[name] = subprocess.Popen(
            list(args), stdin=subprocess.DEVNULL, start_new_session=True,
            preexec_fn=self._preexec, pass_fds=tuple(pass_fds),
            # a Python process that hangs prints its threads' stacks at SIGABRT
            env={'PYTHONFAULTHANDLER': '1', **os.environ})

    def started(self) -> bool:
        """Tell whether a process was started."""
        return bool(self._processes)

    def watch(self) -> None:
        """Start watching the processes."""
        self._watch.start()

    def state(self, name: str) -> str:
        """
        Return the state of the process of an instance: starting, running or exited.

        The manager's services answer from the start, before every process
        is started: one not started yet is starting.
        """
        process = self._processes.get(name)
        if process is None:
            return 'starting'
        return 'running' if process.poll() is None else 'exited'

    def _watch_loop(self) -> None:
        reported: Dict[str, subprocess.Popen[bytes]] = {}
        while not self._stopping.wait(0.1):
            for name, process in list(self._processes.items()):
                code = process.poll()
                # a process started again is watched again
                if code is not None and reported.get(name) is not process:
                    reported[name] = process
                    self.on_exit(name, code)

    def interrupt(self, name: str) -> None:
        """
        Ask one process to end (SIGINT) now, the system being stopped; stop() waits for it.

        A second SIGINT would tell it to end at once: it gets none from stop().
        """
        self._stopping.set()
        self._interrupted.add(name)
        process = self._processes.get(name)
        if process is not None and process.poll() is None:
            self._signal(process, signal.SIGINT)

    def stop(self, timeout: float = STOP_TIMEOUT) -> bool:
        """
        Ask every process to end (SIGINT), then kill what is left after timeout.

        A process left gets SIGABRT first: a Python one prints where each of
        its threads is (``PYTHONFAULTHANDLER``), which names the hang.

        :returns: whether every process ended of SIGINT, none needing SIGKILL
        """
        self._stopping.set()
        for name in self._processes:
            if name not in self._interrupted:
                self.interrupt(name)
        late = self._wait(self._processes, timeout)
        # never expected: a process ends within a few seconds of SIGINT. One
        # at a time, so that the stacks do not run into each other; those
        # left after twice ABORT_GRACE are killed as they are
        deadline = time.monotonic() + 2 * ABORT_GRACE
        for name in late:
            if time.monotonic() >= deadline:
                say('error', f'{name} did not end within {timeout:g} s of SIGINT: SIGKILL')
                continue
            say('error', f'{name} did not end within {timeout:g} s of SIGINT: SIGABRT, '
                'for the stacks of its threads, then SIGKILL')
            self._signal(self._processes[name], signal.SIGABRT)
            self._wait({name: self._processes[name]},
                       min(ABORT_GRACE, deadline - time.monotonic()))
        if late:
            self.kill()
        return not late

    @staticmethod
    def _wait(processes: Dict[str, subprocess.Popen[bytes]], timeout: float) -> List[str]:
        """Wait for the processes to end within timeout; return the names of those that did not."""
        deadline = time.monotonic() + timeout
        late = []
        for name, process in processes.items():
            try:
                process.wait(max(0.0, deadline - time.monotonic()))
            except subprocess.TimeoutExpired:
                late.append(name)
        return late

    @staticmethod
    def _signal(process: subprocess.Popen[bytes], signum: int) -> None:
        try:
            os.killpg(process.pid, signum)
        except ProcessLookupError:
            pass

    def kill(self) -> None:
        """End every process at once."""
        self._stopping.set()
        for process in self._processes.values():
            self._signal(process, signal.SIGKILL)


def node_arguments(instance: Dict[str, Any], params_file: str) -> List[str]:
    """Return the ROS arguments of the node of an instance (remappings, parameters)."""
    args = ['--params-file', params_file]
    for source, target in instance['remappings']:
        args += ['-r', f'{source}:={target}']
    return args


#: group name -> (its instances, its command line)
Groups = Dict[str, Tuple[List[str], List[str]]]


class NotInstalled(Exception):
    """Packages that instances of a host need are not installed: nothing was started."""

    def __init__(self, problems: List[str]) -> None:
        super().__init__('\n'.join(problems))
        #: one line per missing package, naming the instances that need it
        self.problems = problems


def _check_installed(needs: Dict[str, List[str]]) -> None:
    """
    Raise :class:`NotInstalled` for every package of ``needs`` that is not installed.

    :param needs: package -> the instances that need it
    """
    problems = []
    for package, instances in needs.items():
        try:
            get_package_prefix(package)
        except PackageNotFoundError:
            which = ', '.join(instances)
            problems.append(
                f"instance{'s' if len(instances) > 1 else ''} {which} need"
                f"{'' if len(instances) > 1 else 's'} the package '{package}', which is not "
                'installed (no prefix of AMENT_PREFIX_PATH has it: build it, or source the '
                'install that has it)')
    if problems:
        raise NotInstalled(problems)


#: the group of the Python instances of the manager's host in one process
PYTHON_GROUP = 'python instances'
#: the group of the C++ instances in a shared component container
CPP_GROUP = 'C++ instances'


def plan_processes(description: Dict[str, Any], description_file: str, params_file: str,
                   host: str = '', shared: Optional[bool] = None,
                   report_fds: Optional[Dict[str, int]] = None) -> Groups:
    """
    Return the processes that run the instances of a host ('' for the manager's).

    :param shared: whether the Python instances share one process, and the
        C++ ones one component container; by default what the model says
        (``processes: shared``)
    :param report_fds: group -> where its process on the manager's host writes
        the states it brought its instances to (``--report-fd``)
    :raises NotInstalled: when a package that an instance needs is not installed
    """
    instances = [i for i in description['instances'] if i.get('host', '') == host]
    together = shared_python(description, host, shared)
    loaded = shared_cpp(description, host, shared)
    needs: Dict[str, List[str]] = {}
    for instance in instances:
        if not instance.get('command'):
            needs.setdefault(instance['package'], []).append(instance['instance'])
    _check_installed(needs)
    if loaded and not os.path.exists(container_program(description['package'])):
        raise NotInstalled([
            f"instance{'s' if len(loaded) > 1 else ''} {', '.join(loaded)} need"
            f"{'' if len(loaded) > 1 else 's'} the component container of the package "
            f"'{description['package']}', which was built without rclcpp_components (build it "
            'again where rclcpp_components is installed)'])
    # what bringup's options give every process (--log-level)
    ros_arguments = list(description.get('ros_arguments', ()))
    groups: Groups = {}
    for instance in instances:
        if instance['instance'] not in together and instance['instance'] not in loaded:
            groups[instance['instance']] = (
                [instance['instance']], command(instance, params_file) + ros_arguments)
    # one process for each language, not one per CPU: two made 50 nodes up in
    # 1.7 s, one in 1.2 s (each process is a DDS participant the others
    # discover); on the manager's host each brings up what it can by itself
    # and tells what it brought up: the manager finds those active
    for group, names, module in ((PYTHON_GROUP, together, 'container'),
                                 (CPP_GROUP, loaded, 'cpp_container')):
        if not names:
            continue
        fd = (report_fds or {}).get(group)
        groups[group + (f' on {host}' if host else '')] = (names, [
            sys.executable, '-m', f'robmosys_runtime.{module}',
            *([] if host else ['--activate']),
            *(['--report-fd', str(fd)] if fd is not None and not host else []),
            description_file, params_file, *names] +
            (['--ros-args', *ros_arguments] if ros_arguments else []))
    return groups


def container_program(package: str) -> str:
    """
    Return the component container of a system package's C++ instances.

    robmosys_runtime's ``src/component_container.cpp``, which the package
    builds where rclcpp_components is installed.
    """
    return os.path.join(get_package_prefix(package), 'lib', package, 'component_container')


def shared_python(description: Dict[str, Any], host: str = '',
                  shared: Optional[bool] = None) -> List[str]:
    """
    Return the Python instances of a host that share one process (none if not shared).

    On the manager's host ('') that process brings them up by itself and
    tells the manager what it brought up (``container --activate``), from
    ``bringup`` as from ``<system>.launch.py``.
    """
    return _shared(description, host, shared, 'python_class')


def shared_cpp(description: Dict[str, Any], host: str = '',
               shared: Optional[bool] = None) -> List[str]:
    """
    Return the C++ instances of a host that share one component container (none if not).

    On the manager's host it brings them up by itself, as the Python process
    does (``cpp_container --activate``).
    """
    return _shared(description, host, shared, 'plugin')


def _shared(description: Dict[str, Any], host: str, shared: Optional[bool],
            start: str) -> List[str]:
    """Return the instances of a host that a shared process creates by ``start``."""
    if shared is None:
        shared = description.get('processes') == 'shared'
    return [i['instance'] for i in description['instances'] if shared and
            i.get('host', '') == host and i.get(start) and not i.get('command')]


class SharedArguments(NamedTuple):
    """
    The command line of a shared process (``container``, ``cpp_container``).

    ``[--activate [--report-fd FD | --report-file FILE]] DESCRIPTION
    PARAMS_FILE INSTANCE... [--ros-args ...]``
    """

    activate: bool
    report_fd: Optional[int]
    report_file: Optional[str]
    description_file: str
    params_file: str
    names: List[str]
    #: what follows --ros-args: the process's own (--log-level)
    ros_arguments: List[str]


def shared_arguments(argv: List[str]) -> Optional[SharedArguments]:
    """Return the arguments of a shared process's command line, None if it is not one."""
    ros_arguments = argv[argv.index('--ros-args'):] if '--ros-args' in argv else []
    args = argv[:len(argv) - len(ros_arguments)]
    activate = args[:1] == ['--activate']
    args = args[1:] if activate else args
    report_fd: Optional[int] = None
    report_file: Optional[str] = None
    if activate and args[:1] == ['--report-fd'] and len(args) > 1 and args[1].isdigit():
        report_fd = int(args[1])
        args = args[2:]
    elif activate and args[:1] == ['--report-file'] and len(args) > 1:
        report_file = args[1]
        args = args[2:]
    if len(args) < 3 or args[0].startswith('--'):
        # too few, or an option it does not know (--report-fd without a number)
        return None
    return SharedArguments(activate, report_fd, report_file, args[0], args[1], args[2:],
                           ros_arguments)
