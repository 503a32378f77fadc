# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""
The processes of a system's instances: their command lines, grouped.

One process per instance runs the instance's executable with the arguments
launch_ros would give it. With ``processes: shared`` the Python instances of
a host share one multi-threaded process (:mod:`robmosys_runtime.hosting.container`):
a 50-instance system then does not start 50 Python interpreters.
:mod:`robmosys_runtime.hosting.supervision` starts, watches and stops them.
"""

from __future__ import annotations

import os
import sys
from typing import Any, Dict, List, NamedTuple, Optional, Tuple

from ament_index_python.packages import get_package_prefix, PackageNotFoundError


def command(instance: Dict[str, Any], params_file: str) -> List[str]:
    """Return the command line of an instance, as launch_ros would build it."""
    executable = instance.get('command') or [os.path.join(
        get_package_prefix(instance['package']), 'lib', instance['package'],
        instance['executable'])]
    args = list(executable) + ['--ros-args', '-r', f"__node:={instance['name']}"]
    if instance['namespace']:
        args += ['-r', f"__ns:={instance['namespace']}"]
    return args + node_arguments(instance, params_file)


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
            sys.executable, '-m', f'robmosys_runtime.hosting.{module}',
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
