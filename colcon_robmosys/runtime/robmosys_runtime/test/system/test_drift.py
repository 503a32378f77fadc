# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""Instances taken out of active behind the manager's back, and back, on real rclpy."""

import threading
import time

from conftest import wait_until
from rclpy.lifecycle import Node as LifecycleNode
from rclpy.lifecycle import TransitionCallbackReturn
from rclpy.node import Node
from robmosys_runtime.system import drift
from robmosys_runtime.system.activation import SystemActivation
from robmosys_runtime.system.drift import Drift


class Instance(LifecycleNode):
    """A lifecycle node whose configure gives the results it is given, in turn."""

    def __init__(self, name, context, configure=(), cleanup_delay=0.0):
        super().__init__(name, namespace='/system', context=context)
        self._configure = list(configure)
        self._cleanup_delay = cleanup_delay

    def on_configure(self, state):
        return self._configure.pop(0) if self._configure else TransitionCallbackReturn.SUCCESS

    def on_cleanup(self, state):
        time.sleep(self._cleanup_delay)
        return super().on_cleanup(state)


class Followed:
    """Instances brought up by a SystemActivation, their transition events followed."""

    def __init__(self, spinning, monkeypatch, after, **instances) -> None:
        self.said = []
        self.reports = []
        monkeypatch.setattr(drift, 'say', lambda level, text: self.said.append((level, text)))
        self.nodes = {n: spinning.add(Instance(n, spinning.context, **instances.get(n, {})))
                      for n in after}
        manager = spinning.add(Node('manager', context=spinning.context))
        self.activation = SystemActivation(
            manager, {n: f'/system/{n}' for n in after}, after, timeout=10.0,
            report=lambda level, text: self.reports.append((level, text)))
        self.up = True
        self.drift = Drift(self.activation, lambda: self.up)
        self.stopping = threading.Event()
        self.activation.start()
        self.outcome = self.activation.wait(30)
        self.thread = threading.Thread(
            target=self.drift.follow, args=(manager, {n: f'/system/{n}' for n in after},
                                            self.stopping), daemon=True)
        self.thread.start()
        for name, node in self.nodes.items():
            assert wait_until(lambda: node.count_subscribers(
                f'/system/{name}/transition_event') == 1)

    def stop(self) -> None:
        self.stopping.set()
        self.thread.join(5)
        self.activation.close()


def test_a_deactivation_is_a_failure_until_the_instance_is_active_again(
        spinning, monkeypatch):
    followed = Followed(spinning, monkeypatch, {'a': [], 'b': ['a']})
    try:
        assert followed.outcome.ok, followed.outcome
        a, activation = followed.nodes['a'], followed.activation
        # an operator, behind the manager's back
        a.trigger_deactivate()
        assert wait_until(lambda: activation.states().get('a') == 'failed', 5), followed.said
        assert activation.failures() == {'a': 'is inactive, not active'}
        assert followed.said == [
            ('error', 'instance a is inactive, not active (transition_event)')]
        # the watch is told the state the instance is in
        assert followed.drift.states_for_watch(activation.states()) == {
            'a': 'inactive', 'b': 'active'}
        # once its process ended, not what the process had told: it has none
        followed.drift.ended('a')
        assert followed.drift.states_for_watch(activation.states()) == {
            'a': 'failed', 'b': 'active'}
        # a later state replaces it
        a.trigger_cleanup()
        assert wait_until(lambda: activation.failures() == {
            'a': 'is unconfigured, not active'}, 5), followed.said
        a.trigger_configure()
        a.trigger_activate()
        # back, whatever brought it back: no longer failed
        assert wait_until(lambda: activation.states() == {'a': 'active', 'b': 'active'},
                          5), followed.said
        assert activation.failures() == {}
        assert followed.said[-1] == ('info', 'instance a is active again (transition_event)')
        # b was never touched: it is not brought up again
        assert [r for r in followed.reports if 'instance b' in r[1]] == [
            ('info', 'instance b is active')]
    finally:
        followed.stop()


def test_the_managers_own_transitions_are_no_drift(spinning, monkeypatch):
    followed = Followed(spinning, monkeypatch, {'a': [], 'b': ['a'], 'c': ['b']},
                        b={'cleanup_delay': 1.0})
    try:
        activation = followed.activation
        # down and up again by the manager, while the system is meant to be up:
        # b's deactivation is told while the manager still takes it down
        # (cleaning up takes a second), the events of the others may come after
        # the activation moved on
        for _ in range(2):
            steps = activation.bring_down(timeout=10.0)
            assert len(steps) == 6, steps
            assert set(activation.states().values()) == {'unconfigured'}
            activation.start()
            assert activation.wait(30).ok
        assert not wait_until(lambda: followed.said, 2.0), followed.said
        assert activation.states() == dict.fromkeys('abc', 'active')
        assert activation.failures() == {}
    finally:
        followed.stop()


def test_a_failure_repaired_by_hand_clears_and_what_it_held_back_comes_up(
        spinning, monkeypatch):
    followed = Followed(spinning, monkeypatch, {'a': [], 'b': ['a']},
                        a={'configure': [TransitionCallbackReturn.FAILURE]})
    try:
        assert followed.outcome.failed == {'a': 'failed to configure (it is unconfigured)'}
        assert followed.outcome.held_back == {'b': ['a']}
        a, activation = followed.nodes['a'], followed.activation
        a.trigger_configure()
        # not active yet: still failed, for the reason it failed
        assert not wait_until(lambda: 'a' not in activation.failures(), 1.0)
        assert activation.failures() == {'a': 'failed to configure (it is unconfigured)'}
        a.trigger_activate()
        assert wait_until(lambda: activation.states() == {'a': 'active', 'b': 'active'},
                          10), (followed.said, followed.reports)
        assert ('info', 'instance a is active again (transition_event)') in followed.said
        assert followed.nodes['b']._state_machine.current_state[1] == 'active'
    finally:
        followed.stop()


def test_nothing_is_failed_while_the_system_is_meant_to_be_down(spinning, monkeypatch):
    followed = Followed(spinning, monkeypatch, {'a': []})
    try:
        followed.up = False
        followed.nodes['a'].trigger_deactivate()
        assert not wait_until(lambda: followed.said, 1.5), followed.said
        assert followed.activation.failures() == {}
    finally:
        followed.stop()
