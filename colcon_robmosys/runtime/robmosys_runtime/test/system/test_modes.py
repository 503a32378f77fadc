# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""The modes of a system: the mode chosen at start, the values set, the mode inferred."""

import pytest
from rcl_interfaces.msg import ParameterType
from robmosys_runtime.system.modes import parameter_message
from robmosys_runtime.tools.arguments import ArgumentError, chosen_mode
from robmosys_runtime.watch.check import inferred_mode

DESCRIPTION = {
    'initial_mode': 'docking',
    'instances': [{'instance': 'driver', 'fqn': '/driver', 'managed': True},
                  {'instance': 'lidar', 'fqn': '/lidar', 'managed': True},
                  {'instance': 'talker', 'fqn': '/talker', 'managed': False}],
    'modes': [{'name': 'docking', 'active': ['driver'], 'values': {'driver': {'rate': 2}}},
              {'name': 'cruising', 'active': ['driver', 'lidar'],
               'values': {'driver': {'rate': 40}}}]}


def test_the_mode_a_system_starts_in():
    assert chosen_mode(DESCRIPTION, '') == 'docking'
    assert chosen_mode(DESCRIPTION, ' cruising ') == 'cruising'
    with pytest.raises(ArgumentError, match=r"mode 'parked': the system has no such mode "
                       r'\(its modes: docking, cruising\)'):
        chosen_mode(DESCRIPTION, 'parked')
    with pytest.raises(ArgumentError, match="mode 'docking': the system has no modes"):
        chosen_mode({'instances': []}, 'docking')
    assert chosen_mode({'instances': []}, '') == ''


def test_values_are_sent_with_the_declared_type():
    """An integer of a double parameter is sent as a double: ROS 2 refuses it otherwise."""
    assert parameter_message('gain', 2, 'double').value.type == ParameterType.PARAMETER_DOUBLE
    assert parameter_message('gain', 2, 'double').value.double_value == 2.0
    assert list(parameter_message('w', [1, 2], 'double[]').value.double_array_value) == \
        [1.0, 2.0]
    assert parameter_message('key', [0, 255], 'byte[]').value.type == \
        ParameterType.PARAMETER_BYTE_ARRAY
    assert parameter_message('rate', 3, None).value.type == ParameterType.PARAMETER_INTEGER


def test_the_mode_a_running_system_is_in():
    assert inferred_mode(DESCRIPTION, {'driver': 'active', 'lidar': 'inactive'},
                         {'/driver': {'rate': 2}})[0] == 'docking'
    mode, how = inferred_mode(DESCRIPTION, {'driver': 'active', 'lidar': 'active'},
                              {'/driver': {'rate': 2}})
    assert (mode, how) == ('cruising', 'inferred: the nearest mode; 0 instance(s) in another '
                           'state, 1 value(s) other than its')
