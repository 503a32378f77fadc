# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""
The runtime of RobMoSys components in ROS 2: what generated nodes do not state.

Hand-written nodes use it too: :class:`EventServer` and :class:`EventClient`
serve and use event ports, :class:`QueryClient` and :class:`ActionClientPort`
call queries and actions blocking or asynchronously (see docs/runtime.md).

The modules at the top of the package are the component side: what a
component node is made of (:mod:`.node`, :mod:`.ports`, :mod:`.events`,
:mod:`.parameters` and :mod:`.rules`, :mod:`.activity`, :mod:`.qos`,
:mod:`.announce`, :mod:`.transitions`) and its process (:mod:`.main`,
:mod:`.executors`). They import none of the rooms below, and a hand-written
node needs nothing else. The rooms, each importing only those before it:

- :mod:`robmosys_runtime.tools`: the arguments of a system's start, the
  offline check of parameter files, the smoke test;
- :mod:`robmosys_runtime.hosting`: the processes of a system's instances,
  the shared ones, and what they tell the manager;
- :mod:`robmosys_runtime.watch`: the conformance watch;
- :mod:`robmosys_runtime.system`: the system manager and ``bringup``.

The names below are imported from their modules when first used: ``bringup``
starts the processes of a system's instances before it imports rclpy (a
third of a second, which the instances spend starting), and importing a
module of this package must not import rclpy for it.
"""

from importlib import import_module
from typing import Any, List, TYPE_CHECKING

if TYPE_CHECKING:
    from robmosys_runtime.activity import Activity  # noqa: F401
    from robmosys_runtime.events import (  # noqa: F401
        copy_fields, EventActivation, EventClient, EventServer)
    from robmosys_runtime.executors import executor_threads  # noqa: F401
    from robmosys_runtime.main import run  # noqa: F401
    from robmosys_runtime.node import ComponentNode  # noqa: F401
    from robmosys_runtime.parameters import (  # noqa: F401
        map_entries, ParameterRule, ParameterRules, required_set)
    from robmosys_runtime.ports import ActionClientPort, QueryClient, wait_for  # noqa: F401

__version__ = '0.1.0'

#: each name of the package -> the module that defines it
_MODULES = {
    'ActionClientPort': 'ports', 'Activity': 'activity', 'ComponentNode': 'node',
    'EventActivation': 'events', 'EventClient': 'events', 'EventServer': 'events',
    'ParameterRule': 'parameters', 'ParameterRules': 'parameters', 'QueryClient': 'ports',
    'copy_fields': 'events', 'executor_threads': 'executors', 'map_entries': 'parameters',
    'required_set': 'parameters',
    'run': 'main', 'wait_for': 'ports',
}

__all__ = sorted(_MODULES)


def __getattr__(name: str) -> Any:
    """Import a name of the package from its module, the first time it is used."""
    module = _MODULES.get(name)
    if module is None:
        raise AttributeError(f'module {__name__!r} has no attribute {name!r}')
    value = getattr(import_module(f'{__name__}.{module}'), name)
    globals()[name] = value
    return value


def __dir__() -> List[str]:
    """List the names of the package, imported or not."""
    return sorted(set(globals()) | set(_MODULES))
