# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""The states lifecycle nodes tell on their transition events, on real rclpy."""

from conftest import wait_until
from rclpy.lifecycle import Node as LifecycleNode
from rclpy.node import Node
from robmosys_runtime.watch.states import LifecycleStates


def _follow(spinning, names):
    nodes = {n: spinning.add(LifecycleNode(n, namespace='/system', context=spinning.context))
             for n in names}
    watcher = spinning.add(Node('watcher', context=spinning.context))
    told = []
    states = LifecycleStates(watcher, {n: f'/system/{n}' for n in names},
                             on_state=lambda name, state: told.append((name, state)))
    for name, node in nodes.items():
        # one participant: matched once the graph shows the subscription
        assert wait_until(lambda: node.count_subscribers(
            f'/system/{name}/transition_event') == 1)
    return nodes, states, told


def test_each_state_reached_is_told_in_order_and_kept(spinning):
    nodes, states, told = _follow(spinning, ['a', 'b'])
    a = nodes['a']
    assert states.state('a') is None and states.states() == {}
    a.trigger_configure()
    a.trigger_activate()
    a.trigger_deactivate()
    a.trigger_cleanup()
    a.trigger_shutdown()
    assert wait_until(lambda: len(told) == 5), told
    # the states on the way (configuring, activating...) are not told
    assert told == [('a', 'inactive'), ('a', 'active'), ('a', 'inactive'),
                    ('a', 'unconfigured'), ('a', 'finalized')]
    assert states.state('a') == 'finalized'
    # nothing is known of a node that made no transition
    assert states.state('b') is None and states.states() == {'a': 'finalized'}


def test_a_state_reached_again_is_told_again_and_close_ends_it(spinning):
    nodes, states, told = _follow(spinning, ['a'])
    a = nodes['a']
    a.trigger_configure()
    assert wait_until(lambda: told == [('a', 'inactive')]), told
    a.trigger_activate()
    a.trigger_deactivate()
    assert wait_until(lambda: len(told) == 3), told
    states.close()
    assert wait_until(lambda: a.count_subscribers('/system/a/transition_event') == 0)
    a.trigger_cleanup()
    assert not wait_until(lambda: len(told) > 3, timeout=1.0), told
    assert states.state('a') == 'inactive'
