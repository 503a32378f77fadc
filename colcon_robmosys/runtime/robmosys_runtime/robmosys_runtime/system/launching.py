# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""
The launch arguments of a system's launch files, and what every node is given of them.

A generated launch file makes one :class:`SystemArguments` and hands each node
action the same things: its namespace and ROS names through :meth:`moved`,
``parameters`` and ``ros_arguments``; the shared Python process
(``processes: shared``) is given ``description`` and ``params_file``, files
whose names and values are moved and set as the nodes' are. The arguments mean what bringup's
options mean (:mod:`robmosys_runtime.tools.arguments`); launch and launch_ros are
imported here only, by launch files. Its ``check`` action, before every process,
refuses what bringup refuses (:func:`check_arguments`).
"""

from __future__ import annotations

import atexit
import json
import os
import shutil
import sys
import tempfile
from typing import Any, Dict, List, Optional, Text, Tuple

from ament_index_python.packages import get_package_prefix, get_package_share_directory
from launch.actions import DeclareLaunchArgument, OpaqueFunction
from launch.launch_context import LaunchContext
from launch.substitution import Substitution
from launch.substitutions import LaunchConfiguration, SubstitutionFailure
from robmosys_runtime.hosting.processes import CPP_GROUP
from robmosys_runtime.hosting.told import told_file
from robmosys_runtime.tools.arguments import (
    ArgumentError, ARGUMENTS, chosen_mode, LOG_LEVELS, moved, moved_description,
    normalized_namespace, parameters_file, sim_time, temporary)
from robmosys_runtime.tools.paramcheck import check_operator_file


def _argument(context: LaunchContext, name: str) -> str:
    return str(context.launch_configurations.get(name, ARGUMENTS[name][0]))


def namespace(context: LaunchContext) -> str:
    """Return the namespace argument, normalized ('' for none)."""
    return normalized_namespace(_argument(context, 'namespace'))


class Moved(Substitution):
    """A ROS name of the model (a namespace, a topic), moved into the namespace argument."""

    def __init__(self, name: str) -> None:
        super().__init__()
        self.name = name

    def describe(self) -> Text:
        """Return the name, for launch's messages."""
        return f'Moved({self.name!r})'

    def perform(self, context: LaunchContext) -> Text:
        """Return the name in the namespace; the root namespace ('') is that namespace."""
        return moved(namespace(context), self.name or '/')


class Program(Substitution):
    """
    A program of a package, ``lib/<package>/<name>``: what ``ros2 run`` runs.

    What launch_ros' ``Node(package=, executable=)`` finds, without
    launch_ros: a launch file whose every process is started this way
    imports no rclpy.
    """

    def __init__(self, package: str, name: str) -> None:
        super().__init__()
        self.package = package
        self.name = name

    def describe(self) -> Text:
        """Return what it is, for launch's messages."""
        return f'Program({self.package!r}, {self.name!r})'

    def perform(self, context: LaunchContext) -> Text:
        """Return the path of the program; fail if the package does not install it."""
        path = os.path.join(get_package_prefix(self.package), 'lib', self.package, self.name)
        if not os.access(path, os.X_OK):
            raise SubstitutionFailure(
                f"package '{self.package}' installs no program {self.name} ({path})")
        return path


#: (package, namespace, use_sim_time, operator's file) -> the file made for them
_FILES: Dict[Tuple[str, str, Optional[bool], str], str] = {}


def _description(package: str) -> Dict[str, Any]:
    share = get_package_share_directory(package)
    with open(os.path.join(share, 'bringup.json'), encoding='utf-8') as stream:
        return json.load(stream)


#: (package, namespace) -> the description made for them
_DESCRIPTIONS: Dict[Tuple[str, str], str] = {}


class SystemDescription(Substitution):
    """The system's description (bringup.json) the shared Python process reads, moved."""

    def __init__(self, package: str) -> None:
        super().__init__()
        self.package = package

    def describe(self) -> Text:
        """Return what it is, for launch's messages."""
        return f'SystemDescription({self.package!r})'

    def perform(self, context: LaunchContext) -> Text:
        """Return the installed description, or one moved into the namespace argument."""
        where = namespace(context)
        if not where:
            return os.path.join(get_package_share_directory(self.package), 'bringup.json')
        key = (self.package, where)
        if key not in _DESCRIPTIONS:
            _DESCRIPTIONS[key] = temporary(json.dumps(moved_description(
                _description(self.package), where)), 'robmosys_launch_', '.json')
        return _DESCRIPTIONS[key]


#: (package, namespace, operator's file) -> checked (its warnings said)
_CHECKED: Dict[Tuple[str, str, str], bool] = {}


def check_arguments(context: LaunchContext, package: str) -> List[Any]:
    """
    Refuse the launch arguments bringup would refuse, before any process starts.

    A namespace or use_sim_time that is no such value (launch itself holds
    log_level to its choices), an operator's file that is not there or does
    not fit the system (checked as check_params checks it: the line of each
    problem is printed first, bare, for editors).
    Launch cannot exit 2 as bringup does: the error ends the launch before it
    started anything, and ``ros2 launch`` prints it as one line (``Caught
    exception in launch ...: params_file 'site.yaml' does not fit the system
    ...; nothing was started``) and exits 1.

    :raises ArgumentError: what is wrong, in one line
    """
    try:
        where = namespace(context)
        sim_time(_argument(context, 'use_sim_time'))
        chosen_mode(_description(package), _argument(context, 'mode'))
        operator = os.path.expanduser(_argument(context, 'params_file').strip())
        key = (package, where, operator)
        if operator and key not in _CHECKED:
            if not os.path.isfile(operator):
                raise ArgumentError(f'params_file {operator!r}: no such file')
            for line in check_operator_file(_description(package), operator, where):
                print(line, file=sys.stderr, flush=True)
            _CHECKED[key] = True
    except ArgumentError as error:
        for line in getattr(error, 'lines', ()):
            print(line, file=sys.stderr, flush=True)
        raise ArgumentError(f'{error}; nothing was started') from None
    return []


class SystemParameters(Substitution):
    """The parameter file every node of the system reads, for the arguments given."""

    def __init__(self, package: str) -> None:
        super().__init__()
        self.package = package

    def describe(self) -> Text:
        """Return what it is, for launch's messages."""
        return f'SystemParameters({self.package!r})'

    def perform(self, context: LaunchContext) -> Text:
        """Return the system's cfg/params.yaml, or the file made for the arguments."""
        # a launch file without SystemArguments.check: refused all the same
        check_arguments(context, self.package)
        share = get_package_share_directory(self.package)
        description = _description(self.package)
        where = namespace(context)
        operator = os.path.expanduser(_argument(context, 'params_file').strip())
        key = (self.package, where, sim_time(_argument(context, 'use_sim_time')), operator)
        if key not in _FILES:
            # one file for every node of the launch
            _FILES[key] = parameters_file(
                [moved(where, i['fqn']) for i in description['instances']],
                os.path.join(share, description['params_file']), where, key[2], operator)
        return _FILES[key]


#: the launch arguments of the manager's launch files alone: name -> (default, description)
MANAGER_ARGUMENTS = {
    'web': ('', 'a port where the system manager serves a page of the running system '
            '(0: any free one; empty: no page); it prints the address with its token'),
    'web_address': ('127.0.0.1', 'the address the page listens on'),
}


class SystemArguments:
    """The launch arguments of a system, and what each node action is given of them."""

    def __init__(self, package: str) -> None:
        self.package = package
        #: the arguments, declared (``ros2 launch ... --show-args`` lists them)
        self.declarations: List[Any] = [
            DeclareLaunchArgument(
                name, default_value=default, description=description,
                **({'choices': list(LOG_LEVELS)} if name == 'log_level' else {}))
            for name, (default, description) in ARGUMENTS.items()]
        #: what checks the arguments before any process starts (check_arguments):
        #: the first action after the declarations
        self.check = OpaqueFunction(function=check_arguments, args=[package])
        #: the parameter file of every node
        self.params_file = SystemParameters(package)
        #: the ``parameters`` of every node
        self.parameters: List[Any] = [self.params_file]
        #: the description the shared Python process reads
        self.description = SystemDescription(package)
        #: the ``ros_arguments`` of every node's process
        self.ros_arguments: List[Any] = ['--log-level', LaunchConfiguration('log_level')]
        #: the system manager, ``ros2 run <package> bringup``
        self.bringup = Program(package, 'bringup')
        #: the system manager's options of the same meaning, one argument each
        self.manager: List[Any] = [[f"--{name.replace('_', '-')}=", LaunchConfiguration(name)]
                                   for name in [*ARGUMENTS, *MANAGER_ARGUMENTS]]
        #: the arguments of the manager's launch files alone (bringup --web)
        self.manager_declarations: List[Any] = [
            DeclareLaunchArgument(name, default_value=default, description=description)
            for name, (default, description) in MANAGER_ARGUMENTS.items()]
        self._told_file: Optional[str] = None

    @property
    def told_file(self) -> str:
        """
        Return where the shared process writes what it brought up, for the manager.

        A file in a folder of this launch's own, removed when the launch ends:
        the manager reads it before it makes a DDS participant (``bringup
        --told-file``, ``container --report-file``).
        """
        if self._told_file is None:
            folder = tempfile.mkdtemp(prefix=f'robmosys_{self.package}_')
            atexit.register(shutil.rmtree, folder, True)
            self._told_file = os.path.join(folder, 'brought_up.json')
        return self._told_file

    @property
    def cpp_told_file(self) -> str:
        """Return where the C++ component container writes what it brought up (the manager's)."""
        return told_file(self.told_file, CPP_GROUP)

    @staticmethod
    def moved(name: str) -> Moved:
        """Return a namespace or ROS name of the model, moved into the namespace argument."""
        return Moved(name)

    @staticmethod
    def moved_nodes(context: LaunchContext, nodes: Dict[str, str]) -> Dict[str, str]:
        """Return instance -> fully qualified node name, moved into the namespace."""
        where = namespace(context)
        return {instance: moved(where, fqn) for instance, fqn in nodes.items()}
