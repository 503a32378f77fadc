# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""The entries of an array that mapped parameters are repeated for, on a real rclpy node."""

import pytest
from rclpy.node import Node
from robmosys_runtime import map_entries


def _node(spinning, joints):
    node = spinning.add(Node('mapped', context=spinning.context))
    node.declare_parameter('joints', joints)
    node.declare_parameter('wrist.gain', 1.0)
    return node


def test_the_entries_are_returned_in_their_order(spinning):
    node = _node(spinning, ['shoulder', 'elbow'])
    assert map_entries(node, 'joints', ['{}.gain', 'gains.{}.p']) == ['shoulder', 'elbow']


@pytest.mark.parametrize('joints, problem', [
    (['a', 'a'], "entry 'a' is listed twice"),
    (['a.b'], "entry 'a.b' is not a parameter name part (a letter, then letters, digits "
              'and single underscores)'),
    (['a__b'], "entry 'a__b' is not a parameter name part"),
    (['1a'], "entry '1a' is not a parameter name part"),
    (['wrist'], "entry 'wrist' gives the parameter 'wrist.gain', which the component has"),
])
def test_entries_that_cannot_name_parameters_are_refused(spinning, joints, problem):
    node = _node(spinning, joints)
    with pytest.raises(ValueError) as raised:
        map_entries(node, 'joints', ['{}.gain'])
    assert str(raised.value).startswith(f"parameter 'joints': {problem}")
