# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""SystemActivation on real rclpy lifecycle nodes: order, failures, hangs, absences."""

import threading
import time

from rclpy.lifecycle import Node as LifecycleNode
from rclpy.lifecycle import TransitionCallbackReturn
from rclpy.node import Node
from robmosys_runtime.system.activation import SystemActivation

SUCCESS = TransitionCallbackReturn.SUCCESS
FAILURE = TransitionCallbackReturn.FAILURE


class Instance(LifecycleNode):
    """A lifecycle node that records when it goes through its transitions."""

    def __init__(self, name, context, journal, configure=SUCCESS, activate_delay=0.0):
        super().__init__(name, namespace='/system', context=context)
        self._journal = journal
        self._configure = configure
        self._activate_delay = activate_delay

    def on_configure(self, state):
        self._journal.append(('configure', self.get_name(), time.monotonic()))
        return self._configure

    def on_activate(self, state):
        time.sleep(self._activate_delay)
        self._journal.append(('activate', self.get_name(), time.monotonic()))
        return super().on_activate(state)


def _activation(spinning, names, after, timeout=10.0, **instances):
    journal, reports = [], []
    for name in names:
        spinning.add(Instance(name, spinning.context, journal, **instances.get(name, {})))
    driver = spinning.add(LifecycleNode('driver', context=spinning.context))
    activation = SystemActivation(
        driver, {name: f'/system/{name}' for name in names}, after, timeout=timeout,
        report=lambda level, text: reports.append((level, text)))
    return activation, journal, reports


def test_every_instance_is_configured_at_once_and_activated_in_order(spinning):
    after = {'b': ['a'], 'c': ['b'], 'd': []}
    activation, journal, reports = _activation(spinning, ['a', 'b', 'c', 'd'], after,
                                               a={'activate_delay': 1.0})
    activation.start()
    outcome = activation.wait(30)
    assert outcome.ok and outcome.active == ['a', 'b', 'c', 'd'], (outcome, reports)
    # each activation is reported, in the order it happened
    told = [text.split()[1] for level, text in reports]
    assert {level for level, _ in reports} == {'info'} and sorted(told) == ['a', 'b', 'c', 'd']
    assert told.index('a') < told.index('b') < told.index('c')
    activated = [name for step, name, _ in journal if step == 'activate']
    assert activated.index('a') < activated.index('b') < activated.index('c')
    # configured at once: none waits for the (slow) activation of a to configure
    a_active = next(t for step, name, t in journal if (step, name) == ('activate', 'a'))
    assert sorted(n for s, n, t in journal if s == 'configure' and t < a_active) == \
        ['a', 'b', 'c', 'd']


def test_a_failure_is_reported_with_what_it_holds_back(spinning):
    after = {'b': ['a'], 'c': ['b'], 'd': []}
    activation, _, reports = _activation(spinning, ['a', 'b', 'c', 'd'], after,
                                         a={'configure': FAILURE})
    started = time.monotonic()
    activation.start()
    outcome = activation.wait(30)
    # c waits for b, which waits for a: both are held back at once, and the
    # bring-up ends (bringup waits while it runs: it hung here before)
    assert not activation.running() and time.monotonic() - started < 10
    assert outcome.failed == {'a': 'failed to configure (it is unconfigured)'}
    assert outcome.held_back == {'b': ['a'], 'c': ['a']}
    assert outcome.active == ['d']
    assert [r for r in reports if r[0] == 'error'] == [
        ('error', 'instance a failed to configure (it is unconfigured); '
                  'not activated because of it: b, c')]


def test_an_instance_that_never_answers_is_reported_within_its_timeout(spinning):
    activation, _, reports = _activation(spinning, ['slow', 'fine'], {}, timeout=1.5,
                                         slow={'activate_delay': 4.0})
    started = time.monotonic()
    activation.start()
    outcome = activation.wait(30)
    assert time.monotonic() - started < 4.0
    assert outcome.active == ['fine']
    assert 'did not activate within 1.5 s' in outcome.failed['slow']
    assert [level for level, _ in reports] == ['info', 'error']


def test_an_instance_that_never_appears_is_reported(spinning):
    spinning.add(Instance('here', spinning.context, []))
    driver = spinning.add(LifecycleNode('driver', context=spinning.context))
    activation = SystemActivation(
        driver, {'here': '/system/here', 'absent': '/system/absent'}, {}, timeout=1.0,
        report=lambda level, text: None)
    activation.start()
    outcome = activation.wait(30)
    assert outcome.failed == {
        'absent': 'did not appear within 1 s (no node /system/absent in the ROS graph)'}
    assert outcome.active == ['here']


def test_an_instance_that_is_no_lifecycle_node_is_told_apart(spinning):
    # a plain node where the model has a managed instance: it is in the graph,
    # its lifecycle services are not
    spinning.add(Node('plain', namespace='/system', context=spinning.context))
    driver = spinning.add(LifecycleNode('driver', context=spinning.context))
    activation = SystemActivation(driver, {'plain': '/system/plain'}, {}, timeout=1.0,
                                  report=lambda level, text: None)
    activation.start()
    outcome = activation.wait(30)
    assert outcome.failed == {'plain': 'did not appear within 1 s (its node is in the ROS '
                                       'graph, without a get_state service)'}


def test_a_stopped_bring_up_ends_quietly(spinning):
    activation, _, reports = _activation(spinning, ['a', 'b'], {'b': ['a']}, timeout=20.0,
                                         a={'activate_delay': 3.0})
    activation.start()
    time.sleep(0.5)
    activation.stop()
    outcome = activation.wait(10)
    assert [r for r in reports if r[0] == 'error'] == []
    assert 'b' not in outcome.active
    assert not any(t.is_alive() for t in threading.enumerate() if t.name == 'activate b')


def test_lines_of_parallel_transitions_never_run_into_each_other(capfd):
    """Threads that report at once give whole lines, one each (print() wrote two pieces)."""
    from robmosys_runtime.hosting.output import say
    barrier = threading.Barrier(16)

    def report(thread):
        barrier.wait()
        for index in range(50):
            say('info', f'instance beat_{thread}_{index} is active')

    threads = [threading.Thread(target=report, args=(t,)) for t in range(16)]
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join()
    lines = capfd.readouterr().out.split('\n')
    assert lines.pop() == ''
    assert len(lines) == 16 * 50
    assert all(line.startswith('bringup: instance beat_') and line.endswith(' is active') and
               line.count('bringup:') == 1 for line in lines), lines
