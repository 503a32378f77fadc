# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""What the shared Python process brings up by itself (``container --activate``), on real nodes."""

import os

from rclpy.lifecycle import LifecycleNode, TransitionCallbackReturn
from rclpy.parameter import Parameter
from robmosys_runtime import required_set
from robmosys_runtime.hosting.container import activate_in_order, bring_down
from robmosys_runtime.hosting.told import read_steps


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


class _Journaled(LifecycleNode):
    """A lifecycle node that records its deactivation and cleanup, or refuses to deactivate."""

    def __init__(self, name, context, journal, refuse_deactivate=False):
        super().__init__(name, context=context)
        self._journal = journal
        self._refuse = refuse_deactivate

    def on_deactivate(self, state):
        if self._refuse:
            return TransitionCallbackReturn.FAILURE
        self._journal.append(f'deactivate {self.get_name()}')
        return super().on_deactivate(state)

    def on_cleanup(self, state):
        self._journal.append(f'cleanup {self.get_name()}')
        return super().on_cleanup(state)


def _told_steps(instances, nodes):
    """Bring the nodes down into a pipe as the shared process does; return what bringup reads."""
    reading, writing = os.pipe()
    bring_down(instances, nodes, os.fdopen(writing, 'w', encoding='utf-8'))
    try:
        return list(read_steps(reading, wait=5.0))
    finally:
        os.close(reading)


def test_the_process_brings_its_instances_down_itself_the_last_first(spinning):
    journal = []
    names = ('first', 'second', 'unmanaged', 'never_up')
    nodes = [spinning.add(_Journaled(n, spinning.context, journal)) for n in names]
    instances = [{'instance': 'first', 'managed': True},
                 {'instance': 'second', 'managed': True, 'after': ['first']},
                 {'instance': 'unmanaged', 'managed': False},
                 {'instance': 'never_up', 'managed': True}]
    for node in nodes[:3]:
        node.trigger_configure()
        node.trigger_activate()
    steps = _told_steps(instances, nodes)
    # what comes after another goes down first; each step is told as it is done
    assert steps == [('info', 'deactivate second'), ('info', 'cleanup second'),
                     ('info', 'deactivate first'), ('info', 'cleanup first')]
    assert journal == [text for _, text in steps]
    # an unmanaged instance is not the system's to bring down; one never up stays so
    assert [_state(n) for n in nodes] == ['unconfigured', 'unconfigured', 'active',
                                          'unconfigured']


def test_a_transition_that_fails_in_the_bring_down_is_told_and_the_others_go_on(spinning):
    journal = []
    nodes = [spinning.add(_Journaled('steady', spinning.context, journal)),
             spinning.add(_Journaled('stubborn', spinning.context, journal,
                                     refuse_deactivate=True))]
    instances = [{'instance': 'steady', 'managed': True},
                 {'instance': 'stubborn', 'managed': True, 'after': ['steady']}]
    for node in nodes:
        node.trigger_configure()
        node.trigger_activate()
    assert _told_steps(instances, nodes) == [
        ('error', 'instance stubborn could not be brought down: failed to deactivate '
                  '(it is active)'),
        ('info', 'deactivate steady'), ('info', 'cleanup steady')]
    assert [_state(n) for n in nodes] == ['unconfigured', 'active']


def test_the_steps_end_with_the_pipe_or_a_silence_and_skip_the_bring_up_line():
    reading, writing = os.pipe()
    os.write(writing, b'{"first": "active"}\ndeactivate first\ncleanup fi')
    steps = read_steps(reading, wait=0.3)
    assert next(steps) == ('info', 'deactivate first')
    os.write(writing, b'rst\n')
    assert next(steps) == ('info', 'cleanup first')
    # nothing more within wait: a transition that hangs ends the reading
    assert list(steps) == []
    os.close(writing)
    assert list(read_steps(reading, wait=5.0)) == []
    os.close(reading)
