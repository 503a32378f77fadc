# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""
The runtime of RobMoSys components in ROS 2: what generated nodes do not state.

Hand-written nodes use it too: :class:`EventServer` and :class:`EventClient`
serve and use event ports, :class:`QueryClient` and :class:`ActionClientPort`
call queries and actions blocking or asynchronously (see docs/runtime.md).
"""

from robmosys_runtime.events import copy_fields, EventActivation, EventClient, EventServer
from robmosys_runtime.main import executor_threads, run
from robmosys_runtime.node import Activity, ComponentNode
from robmosys_runtime.parameters import ParameterRule, ParameterRules
from robmosys_runtime.ports import ActionClientPort, QueryClient, wait_for

__version__ = '0.1.0'

__all__ = [
    'ActionClientPort', 'Activity', 'ComponentNode', 'EventActivation', 'EventClient',
    'EventServer', 'ParameterRule', 'ParameterRules', 'QueryClient', 'copy_fields',
    'executor_threads', 'run', 'wait_for',
]
