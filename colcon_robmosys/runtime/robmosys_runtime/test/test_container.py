# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""What the shared Python process brings up by itself (``container --activate``), on real nodes."""

from rclpy.lifecycle import LifecycleNode, TransitionCallbackReturn
from rclpy.parameter import Parameter
from robmosys_runtime import required_set
from robmosys_runtime.container import activate_in_order


class _Required(LifecycleNode):
    """A node with a parameter without default, configured as a generated one is."""

    def __init__(self, name, context, **kwargs):
        super().__init__(name, context=context, **kwargs)
        self.declare_parameter('station', Parameter.Type.STRING)

    def on_configure(self, state):
        if not required_set(self, ['station']):
            return TransitionCallbackReturn.FAILURE
        return super().on_configure(state)


def _state(node):
    return node._state_machine.current_state[1]


def test_an_instance_without_its_required_parameter_is_left_to_the_manager(spinning):
    given = Parameter('station', Parameter.Type.STRING, 'dock')
    nodes = [spinning.add(_Required('first', spinning.context, parameter_overrides=[given])),
             spinning.add(_Required('unset', spinning.context)),
             spinning.add(_Required('after_unset', spinning.context,
                                    parameter_overrides=[given])),
             spinning.add(_Required('alone', spinning.context, parameter_overrides=[given]))]
    instances = [{'instance': 'first', 'managed': True},
                 {'instance': 'unset', 'managed': True, 'after': ['first']},
                 {'instance': 'after_unset', 'managed': True, 'after': ['unset']},
                 {'instance': 'alone', 'managed': True}]
    assert activate_in_order(instances, nodes) == ['first', 'alone']
    # the one without its value refused to configure; the one after it waits for the
    # manager, which reports the parameter the node logged
    assert [_state(n) for n in nodes] == ['active', 'unconfigured', 'unconfigured', 'active']


def test_unmanaged_instances_are_not_brought_up(spinning):
    given = Parameter('station', Parameter.Type.STRING, 'dock')
    nodes = [spinning.add(_Required(name, spinning.context, parameter_overrides=[given]))
             for name in ('unmanaged', 'managed')]
    instances = [{'instance': 'unmanaged', 'managed': False},
                 {'instance': 'managed', 'managed': True, 'after': ['unmanaged']}]
    assert activate_in_order(instances, nodes) == []
    assert [_state(n) for n in nodes] == ['unconfigured', 'unconfigured']
