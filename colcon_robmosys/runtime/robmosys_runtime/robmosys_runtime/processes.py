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
from typing import Any, Callable, Dict, List, Optional, Sequence, Tuple

from ament_index_python.packages import get_package_prefix, PackageNotFoundError
from robmosys_runtime.output import say

#: seconds each process has to end after SIGINT, before SIGKILL
STOP_TIMEOUT = 10.0


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
        self._watch = threading.Thread(target=self._watch_loop, daemon=True)

    def start(self, name: str, args: Sequence[str], pass_fds: Sequence[int] = ()) -> None:
        """
        Start an instance in a session of its own: a Ctrl-C reaches only bringup.

        :param pass_fds: file descriptors the process inherits (``--report-fd``)
        """
        self._processes[name] = subprocess.Popen(
            list(args), stdin=subprocess.DEVNULL, start_new_session=True,
            preexec_fn=self._preexec, pass_fds=tuple(pass_fds))

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

    def stop(self, timeout: float = STOP_TIMEOUT) -> None:
        """Ask every process to end (SIGINT), then kill what is left after timeout."""
        self._stopping.set()
        for process in self._processes.values():
            if process.poll() is None:
                try:
                    os.killpg(process.pid, signal.SIGINT)
                except ProcessLookupError:
                    pass
        deadline = time.monotonic() + timeout
        for name, process in self._processes.items():
            try:
                process.wait(max(0.0, deadline - time.monotonic()))
            except subprocess.TimeoutExpired:
                # never expected: a process ends within a few seconds of SIGINT
                say('error', f'{name} did not end within {timeout:g} s of SIGINT: SIGKILL')
                self.kill()

    def kill(self) -> None:
        """End every process at once."""
        self._stopping.set()
        for process in self._processes.values():
            try:
                os.killpg(process.pid, signal.SIGKILL)
            except ProcessLookupError:
                pass


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


#: the group of the C++ instances in a shared component container
CPP_GROUP = 'C++ instances'

#: the executable of rclcpp_components that spins its nodes on each executor
CONTAINERS = {'events': 'component_container_event',
              'single-threaded': 'component_container',
              'multi-threaded': 'component_container_mt'}


def container_executable(description: Dict[str, Any]) -> str:
    """Return the rclcpp_components container of the system's C++ executor (its file name)."""
    executor = description.get('executors', {}).get('cpp', 'multi-threaded')
    folder = os.path.join(get_package_prefix('rclcpp_components'), 'lib', 'rclcpp_components')
    if not os.path.exists(os.path.join(folder, CONTAINERS[executor])):
        # rclcpp_components before component_container_event (Kilted's
        # 29.x has none): one thread, as the events executor has
        return CONTAINERS['single-threaded']
    return CONTAINERS[executor]


def container_node(package: str, host: str = '') -> str:
    """
    Return the node name of the component container of a system's C++ instances.

    :param host: the host whose instances it runs ('' for the manager's host):
      each host has a container of its own, and node names are unique across hosts
    """
    return f'{package}_{host}_container' if host else f'{package}_container'


def container_fqn(description: Dict[str, Any], host: str = '') -> str:
    """Return the fully qualified name of a host's container (moved with the system)."""
    return description.get('namespace', '') + '/' + container_node(description['package'], host)


def plan_processes(description: Dict[str, Any], description_file: str, params_file: str,
                   host: str = '', shared: Optional[bool] = None,
                   containers: bool = True, report_fd: Optional[int] = None) -> Groups:
    """
    Return the processes that run the instances of a host ('' for the manager's).

    :param shared: whether the Python instances share one process, and the
        C++ ones one component container; by default what the model says
        (``processes: shared``)
    :param containers: whether C++ instances may share a container (the
        manager loads them into it, or the bringup of their host: ``CPP_GROUP``)
    :param report_fd: where the shared process of the manager's host writes the
        states it brought its instances to (``container --report-fd``)
    :raises NotInstalled: when a package that an instance needs is not installed
    """
    if shared is None:
        shared = description.get('processes') == 'shared'
    instances = [i for i in description['instances'] if i.get('host', '') == host]
    needs: Dict[str, List[str]] = {}
    for instance in instances:
        if not instance.get('command'):
            needs.setdefault(instance['package'], []).append(instance['instance'])
    loaded_here = [i['instance'] for i in instances
                   if shared and containers and i.get('plugin') and not i.get('command')]
    if loaded_here:
        needs['rclcpp_components'] = loaded_here
    _check_installed(needs)
    # what bringup's options give every process (--log-level)
    ros_arguments = list(description.get('ros_arguments', ()))
    groups: Groups = {}
    together = shared_python(description, host, shared)
    loaded = []
    for instance in instances:
        if instance['instance'] in together:
            continue
        if shared and containers and instance.get('plugin') and not instance.get('command'):
            loaded.append(instance['instance'])
        else:
            groups[instance['instance']] = (
                [instance['instance']], command(instance, params_file) + ros_arguments)
    if together:
        # one process, not one per CPU: two made 50 nodes up in 1.7 s, one in
        # 1.2 s (each process is a DDS participant the others discover)
        # on the manager's host, the process brings up what it can by itself
        # (robmosys_runtime.container); the manager finds those active
        groups['python instances' + (f' on {host}' if host else '')] = (together, [
            sys.executable, '-m', 'robmosys_runtime.container',
            *([] if host else ['--activate']),
            *(['--report-fd', str(report_fd)] if report_fd is not None and not host else []),
            description_file, params_file, *together] +
            (['--ros-args', *ros_arguments] if ros_arguments else []))
    if loaded:
        # rclcpp_components' container of the system's executor; the manager loads the nodes
        groups[CPP_GROUP] = (loaded, [
            os.path.join(get_package_prefix('rclcpp_components'), 'lib', 'rclcpp_components',
                         container_executable(description)),
            '--ros-args', '-r', f"__node:={container_node(description['package'], host)}",
            *_container_namespace(description), *ros_arguments])
    return groups


def shared_python(description: Dict[str, Any], host: str = '',
                  shared: Optional[bool] = None) -> List[str]:
    """
    Return the Python instances of a host that share one process (none if not shared).

    On the manager's host ('') that process brings them up by itself and
    tells the manager what it brought up (``container --activate``), from
    ``bringup`` as from ``<system>.launch.py``.
    """
    if shared is None:
        shared = description.get('processes') == 'shared'
    return [i['instance'] for i in description['instances'] if shared and
            i.get('host', '') == host and i.get('python_class') and not i.get('command')]


def _container_namespace(description: Dict[str, Any]) -> List[str]:
    """Return the remapping that moves the C++ container with its system (bringup --namespace)."""
    return ['-r', f"__ns:={description['namespace']}"] if description.get('namespace') else []
