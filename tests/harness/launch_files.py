# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""What the generated launch files start, read without launch_ros.

launch_ros is not on PyPI, so the tests read a generated ``launch.py`` (as Python
source, never executing it) and start each node with the command line launch_ros
would build; :class:`colcon_robmosys.devtools.system.LifecycleDriver` then drives
the nodes' lifecycle through their real services.
"""

from __future__ import annotations

import ast
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any


@dataclass(frozen=True)
class NodeLaunch:
    """One ``LifecycleNode(...)`` of a generated launch file, as plain data."""

    package: str
    executable: str
    name: str
    namespace: str
    remappings: tuple[tuple[str, str], ...]
    params_files: tuple[Path, ...]
    extra: dict[str, Any] = field(default_factory=dict)
    #: the ROS arguments of its process (the launch argument log_level)
    ros_arguments: tuple[str, ...] = ()

    @property
    def fqn(self) -> str:
        """Return the fully qualified node name."""
        return f"{self.namespace.rstrip('/')}/{self.name}"

    def command(self, install_dir: Path) -> list[str]:
        """Return the command line launch_ros runs for this node."""
        executable = install_dir / self.package / 'lib' / self.package / self.executable
        return [str(executable), *self.ros_args()]

    def ros_args(self) -> list[str]:
        """Return the ``--ros-args`` part of the command line, as launch_ros builds it."""
        args = ['--ros-args', '-r', f'__node:={self.name}']
        if self.namespace:
            args += ['-r', f'__ns:={self.namespace}']
        for params_file in self.params_files:
            args += ['--params-file', str(params_file)]
        for source, target in self.remappings:
            args += ['-r', f'{source}:={target}']
        return args + list(self.ros_arguments)


def _literal(node: ast.AST, names: dict[str, Any]) -> Any:
    if isinstance(node, (ast.Name, ast.Attribute)) and ast.unparse(node) in names:
        return names[ast.unparse(node)]
    if isinstance(node, ast.Call) and ast.unparse(node.func) == 'arguments.moved':
        # a name of the model, moved into the namespace argument: none by default
        return _literal(node.args[0], names)
    if isinstance(node, ast.Tuple):
        return tuple(_literal(item, names) for item in node.elts)
    if isinstance(node, ast.List):
        return [_literal(item, names) for item in node.elts]
    return ast.literal_eval(node)


def nodes_launch_file(share_dir: Path, instance: str = '') -> Path:
    """Return the launch file of a system package that starts its nodes (all, or one)."""
    stem = share_dir.name + (f'.{instance}' if instance else '')
    return share_dir / 'launch' / f'{stem}.nodes.launch.py'


def activate_launch_file(share_dir: Path, instance: str = '') -> Path:
    """Return the launch file of a system package that starts and activates its nodes."""
    stem = share_dir.name + (f'.{instance}' if instance else '')
    return share_dir / 'launch' / f'{stem}.launch.py'


def read_launch_file(path: Path, share_dir: Path) -> list[NodeLaunch]:
    """Return the lifecycle nodes a generated launch file starts.

    :param share_dir: ``share/<system package>`` of the install, where the
      ``params_file`` of the launch file resolves
    """
    tree = ast.parse(path.read_text(encoding='utf-8'), filename=str(path))
    # what robmosys_runtime.system.launching.SystemArguments gives every node when
    # no launch argument is given: the system's parameter file, log level info
    names: dict[str, Any] = {'arguments.parameters': [share_dir / 'cfg' / 'params.yaml'],
                             'arguments.ros_arguments': ['--log-level', 'info']}
    for node in ast.walk(tree):
        # params_file = os.path.join(get_package_share_directory(pkg), 'cfg/...')
        if isinstance(node, ast.Assign) and isinstance(node.value, ast.Call) and \
                len(node.targets) == 1 and isinstance(node.targets[0], ast.Name):
            call = node.value
            first = call.args[0] if call.args else None
            if ast.unparse(call.func) == 'os.path.join' and \
                    isinstance(first, ast.Call) and \
                    ast.unparse(first.func) == 'get_package_share_directory':
                relative = ast.literal_eval(call.args[1])
                names[node.targets[0].id] = share_dir / relative
    nodes = []
    for node in ast.walk(tree):
        # the instances: lifecycle nodes, and plain external nodes (the system
        # manager, a Node too, has no name of an instance)
        if isinstance(node, ast.Call) and \
                ast.unparse(node.func) in ('LifecycleNode', 'Node') and \
                any(k.arg == 'name' for k in node.keywords):
            kwargs = {k.arg: _literal(k.value, names) for k in node.keywords
                      if k.arg is not None}
            nodes.append(NodeLaunch(
                package=kwargs.pop('package'),
                executable=kwargs.pop('executable'),
                name=kwargs.pop('name'),
                namespace=kwargs.pop('namespace', ''),
                remappings=tuple(tuple(r) for r in kwargs.pop('remappings', [])),
                params_files=tuple(Path(p) for p in kwargs.pop('parameters', [])),
                ros_arguments=tuple(kwargs.pop('ros_arguments', ())),
                extra=kwargs))
    return nodes


def read_activate_after(path: Path) -> dict[str, list[str]]:
    """Return the ``ACTIVATE_AFTER`` table of a generated activate file.

    Its keys are the instances the file manages (configures and activates),
    each with the instances that must be active before it is activated.
    """
    tree = ast.parse(path.read_text(encoding='utf-8'), filename=str(path))
    assignment = next(n for n in tree.body if isinstance(n, ast.Assign) and
                      ast.unparse(n.targets[0]) == 'ACTIVATE_AFTER')
    return ast.literal_eval(assignment.value)


def activation_waves(activate_after: dict[str, list[str]]) -> list[list[str]]:
    """Return the managed instances in waves: each once those it comes after are active."""
    waves: list[list[str]] = []
    done: set[str] = set()
    while len(done) < len(activate_after):
        wave = [n for n, after in activate_after.items()
                if n not in done and all(a in done for a in after)]
        if not wave:
            raise ValueError(f'activation order cycle in {activate_after}')
        waves.append(wave)
        done.update(wave)
    return waves
