# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""
The arguments of a system's start, with one meaning for ``ros2 launch`` and ``bringup``.

``use_sim_time``, ``log_level``, ``namespace`` and ``params_file`` are what a
ROS 2 user passes to a system (``ros2 launch <system> <system>.launch.py
use_sim_time:=true``, ``ros2 run <system> bringup --use-sim-time``). The
launch files (:mod:`robmosys_runtime.system.launching`) and bringup apply them with
the functions of this module:

- ``namespace`` moves the whole system: every node and every ROS name of the
  model (``/publisher/pMap`` becomes ``/robot1/publisher/pMap``), the
  entries of the system's parameter file and the topics of its QoS overrides;
- ``use_sim_time`` is set for every node after the system's parameter file;
- ``params_file``, the operator's, is applied after the system's file, so
  that its values win; its entries name the nodes as they run (with the
  namespace), and its wildcards match as ROS 2 matches them.

With none of them given, the nodes read the system's own file, as before. With
one, each node reads one file made here, the values the system's file, the
simulated time and the operator's file give it, in that order (the file of
shared processes and the C++ container, which read one file, too).
"""

from __future__ import annotations

import atexit
import os
import re
from typing import Any, Dict, Iterable, List, Optional, Sequence, Tuple

# yaml and tempfile are imported where used: bringup starts the instances'
# processes before anything else, and most bring-ups need neither (issue 28)

#: the severities of --log-level (rcutils), lowest first
LOG_LEVELS = ('debug', 'info', 'warn', 'error', 'fatal')

#: name -> (default, description): the launch arguments, bringup's options alike
ARGUMENTS: Dict[str, Tuple[str, str]] = {
    'use_sim_time': (
        '', 'true: every node uses the simulated time of /clock; false: the wall clock; '
        "empty: as the system's parameters say"),
    'log_level': (
        'info', 'the lowest severity every node of the system logs: ' + ', '.join(LOG_LEVELS)),
    'namespace': (
        '', 'a namespace that moves the whole system: every node and every ROS name of '
        'the model, e.g. robot1'),
    'params_file': (
        '', "an operator's parameter file, applied after the system's cfg/params.yaml: "
        'its values win'),
    'mode': (
        '', "the mode the system starts in, of a system with modes; empty: the model's "
        'initial mode'),
}


class ArgumentError(ValueError):
    """An argument that cannot be applied: its message says which and why."""


_TOKEN = re.compile(r'^[A-Za-z_][A-Za-z0-9_]*$')


def normalized_namespace(text: str) -> str:
    """
    Return a namespace as ``/a/b``, or '' for none; ``a/b``, ``/a/b/`` are the same.

    :raises ArgumentError: when it is not a ROS 2 namespace
    """
    parts = text.strip().strip('/').split('/') if text.strip('/ ') else []
    for part in parts:
        if not _TOKEN.match(part):
            raise ArgumentError(
                f'namespace {text!r}: {part!r} is not a name of a ROS 2 namespace (letters, '
                'digits and underscores, not starting with a digit)')
    return ''.join(f'/{p}' for p in parts)


def sim_time(text: Optional[str]) -> Optional[bool]:
    """
    Return the value of use_sim_time, or None for "as the system says" ('' or None).

    :raises ArgumentError: when it is not true or false
    """
    if text is None or not text.strip():
        return None
    value = text.strip().lower()
    if value not in ('true', 'false'):
        raise ArgumentError(f'use_sim_time {text!r}: it is true or false')
    return value == 'true'


def chosen_mode(description: Dict[str, Any], text: Optional[str]) -> str:
    """
    Return the mode a system starts in: the one given, else its initial one ('' for none).

    :raises ArgumentError: a mode the system does not have
    """
    value = (text or '').strip()
    modes = [m['name'] for m in description.get('modes', ())]
    if value and not modes:
        raise ArgumentError(f'mode {text!r}: the system has no modes')
    if value and value not in modes:
        raise ArgumentError(f'mode {text!r}: the system has no such mode (its modes: '
                            f"{', '.join(modes)})")
    return value or description.get('initial_mode', '')


def log_level(text: Optional[str]) -> str:
    """
    Return a log level in lower case ('' for none given).

    :raises ArgumentError: when it is not a severity of ROS 2
    """
    value = (text or '').strip().lower()
    if value and value not in LOG_LEVELS:
        raise ArgumentError(f"log_level {text!r}: it is one of {', '.join(LOG_LEVELS)}")
    return value


def moved(namespace: str, name: str) -> str:
    """Return a ROS name of the system moved into a namespace (normalized); relative: as is."""
    if not namespace or not name.startswith('/'):
        return name
    return namespace + name if name != '/' else namespace


def moved_parameter_name(namespace: str, name: str) -> str:
    """Return a parameter's name with the topic of a QoS override moved."""
    prefix = 'qos_overrides.'
    if namespace and name.startswith(prefix + '/'):
        return prefix + moved(namespace, name[len(prefix):])
    return name


def moved_description(description: Dict[str, Any], namespace: str) -> Dict[str, Any]:
    """Return a system's description (bringup.json) with every ROS name moved."""
    if not namespace:
        return description
    instances = []
    for instance in description['instances']:
        instance = dict(instance)
        instance['namespace'] = moved(namespace, instance['namespace'] or '/')
        instance['fqn'] = moved(namespace, instance['fqn'])
        instance['remappings'] = [[source, moved(namespace, target)]
                                  for source, target in instance['remappings']]
        if 'ports' in instance:
            instance['ports'] = [dict(p, name=moved(namespace, p['name']))
                                 for p in instance['ports']]
        if 'parameters' in instance:
            instance['parameters'] = [dict(p, name=moved_parameter_name(namespace, p['name']))
                                      for p in instance['parameters']]
        instances.append(instance)
    connections = [dict(c, name=moved(namespace, c['name']))
                   for c in description.get('connections', ())]
    return dict(description, instances=instances, connections=connections,
                namespace=namespace)


def matches(key: str, fqn: str) -> bool:
    """
    Tell whether an entry of a parameter file applies to a node, as ROS 2 decides.

    A key without its leading ``/`` has it; ``/*`` is one token of the name,
    ``/**`` any number of them (rclcpp's parameter_map, rclpy the same).
    """
    key = key if key.startswith('/') else '/' + key
    pattern = re.escape(key).replace(r'/\*', r'(/\w+)').replace(r'\*', '*')
    return re.fullmatch(pattern, fqn) is not None


def _flattened(tree: Any, prefix: str = '') -> Dict[str, Any]:
    """Return a node's entry as dotted names: nested and dotted forms are one to ROS 2."""
    values: Dict[str, Any] = {}
    for name, value in (tree or {}).items():
        if isinstance(value, dict):
            values.update(_flattened(value, f'{prefix}{name}.'))
        else:
            values[f'{prefix}{name}'] = value
    return values


def _entries(path: str) -> List[Tuple[str, Dict[str, Any]]]:
    """Return the entries of a parameter file: (node key, its values), in order."""
    import yaml
    try:
        with open(path, encoding='utf-8') as stream:
            document = yaml.safe_load(stream)
    except OSError as error:
        raise ArgumentError(f'params_file {path!r}: {error.strerror}') from error
    except yaml.YAMLError as error:
        raise ArgumentError(f'params_file {path!r} is not YAML: {error}') from error
    if document is None:
        return []
    if not isinstance(document, dict):
        raise ArgumentError(f'params_file {path!r}: not a ROS 2 parameter file '
                            '(node name -> ros__parameters)')
    entries: List[Tuple[str, Dict[str, Any]]] = []
    _node_entries(path, document, '', entries)
    return entries


def _node_entries(path: str, tree: Dict[Any, Any], namespace: str,
                  entries: List[Tuple[str, Dict[str, Any]]]) -> None:
    """
    Add the entries of a file's nodes: the keys above ros__parameters make the name.

    ``robot2: {publisher: {ros__parameters: ...}}`` is ``robot2/publisher``, as
    rcl reads it (robmosys_runtime.tools.paramfile says the same, with lines).
    """
    for key, entry in tree.items():
        name = f"{namespace.rstrip('/')}/{key}" if namespace else str(key)
        # below a node's name: its parameters, and the nodes whose names go on
        if not isinstance(entry, dict) or not entry or any(
                not isinstance(value, dict) and not (k == 'ros__parameters' and value is None)
                for k, value in entry.items()):
            raise ArgumentError(f'params_file {path!r}: entry {name!r} has no '
                                'ros__parameters mapping')
        if 'ros__parameters' in entry:
            entries.append((name, _flattened(entry['ros__parameters'])))
        nested = {k: v for k, v in entry.items() if k != 'ros__parameters'}
        if nested:
            _node_entries(path, nested, name, entries)


def node_values(fqns: Iterable[str], system_file: str, namespace: str = '',
                use_sim_time: Optional[bool] = None,
                operator_file: str = '') -> Dict[str, Dict[str, Any]]:
    """
    Return the parameter values each node of a system starts with: fqn -> name -> value.

    :param fqns: the nodes, as they run (moved into ``namespace`` already)
    :param system_file: the system's cfg/params.yaml, whose entries are moved
    """
    # the system's '/**' is for its nodes, which alone read these values
    system = [(key if key == '/**' else moved(namespace, '/' + key.lstrip('/')),
               {moved_parameter_name(namespace, n): v for n, v in values.items()})
              for key, values in _entries(system_file)]
    layers = [system]
    if use_sim_time is not None:
        layers.append([('/**', {'use_sim_time': use_sim_time})])
    if operator_file:
        layers.append(_entries(operator_file))
    result: Dict[str, Dict[str, Any]] = {}
    for fqn in fqns:
        values: Dict[str, Any] = {}
        for layer in layers:
            for key, entry in layer:
                if matches(key, fqn):
                    values.update(entry)
        result[fqn] = values
    return result


def any_given(namespace: str, use_sim_time: Optional[bool], operator_file: str) -> bool:
    """Tell whether the arguments change the parameters: else the system's file serves."""
    return bool(namespace) or use_sim_time is not None or bool(operator_file)


def parameters_file(fqns: Sequence[str], system_file: str, namespace: str = '',
                    use_sim_time: Optional[bool] = None, operator_file: str = '') -> str:
    """
    Return the parameter file the nodes read: the system's, or one made for the arguments.

    The file made holds one entry per node, its values after the system's file,
    the simulated time and the operator's file; it is left in ``directory``
    (the temporary directory), as launch_ros leaves the files of its nodes.
    """
    if not any_given(namespace, use_sim_time, operator_file):
        return system_file
    return written(node_values(fqns, system_file, namespace, use_sim_time, operator_file))


def written(values: Dict[str, Dict[str, Any]]) -> str:
    """Return a parameter file made of the values of each node (see :func:`node_values`)."""
    import yaml
    document = {fqn: {'ros__parameters': v} for fqn, v in values.items()}
    return temporary(yaml.safe_dump(document, default_flow_style=False, sort_keys=False),
                     'robmosys_params_', '.yaml')


def temporary(text: str, prefix: str, suffix: str) -> str:
    """Return a temporary file holding text, removed when the process ends."""
    import tempfile
    handle, path = tempfile.mkstemp(prefix=prefix, suffix=suffix)
    with os.fdopen(handle, 'w', encoding='utf-8') as stream:
        stream.write(text)
    atexit.register(_remove, path)
    return path


def _remove(path: str) -> None:
    try:
        os.remove(path)
    except OSError:
        pass


def without_ros_args(argv: Sequence[str]) -> List[str]:
    """
    Return the arguments without their ROS arguments, as rclpy's remove_ros_args does.

    ``--ros-args`` starts them, ``--`` or the next ``--ros-args`` ends them;
    here without importing rclpy, which the instances are to start with first.
    """
    kept: List[str] = []
    ros = False
    for arg in argv:
        if arg == '--ros-args':
            ros = True
        elif ros and arg == '--':
            ros = False
        elif not ros:
            kept.append(arg)
    return kept


def ros_args_only(argv: Sequence[str]) -> List[str]:
    """
    Return the ROS arguments of argv: what :func:`without_ros_args` leaves out.

    Each ``--ros-args`` is kept with the arguments it starts, so that rcl
    reads them as it would have read them in argv; the ``--`` that ends them
    is left out.
    """
    taken: List[str] = []
    ros = False
    for arg in argv:
        if arg == '--ros-args':
            ros = True
            taken.append(arg)
        elif ros and arg == '--':
            ros = False
        elif ros:
            taken.append(arg)
    return taken
