# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""What the shared process tells the manager it brought up, on real rclpy (reports.py)."""

import threading
import time

from rclpy.lifecycle import Node as LifecycleNode
from rclpy.lifecycle import TransitionCallbackReturn
from robmosys_runtime.activation import SystemActivation
from robmosys_runtime.container import bring_up
from robmosys_runtime.reports import Reporter, reporter_name, Reports

DESCRIPTION = {'package': 'tidy_system', 'namespace': '/robot1'}


def _never():
    return False


class Refusing(LifecycleNode):
    """A lifecycle node whose configure fails."""

    def on_configure(self, state):
        return TransitionCallbackReturn.FAILURE


def _process(spinning, instances, refusing=()):
    """Make the nodes of a shared process and its reporter; return (nodes, reporter)."""
    reporter = Reporter(DESCRIPTION, context=spinning.context)
    reporter.make()
    nodes = [spinning.add((Refusing if i['instance'] in refusing else LifecycleNode)(
        i['instance'], namespace='/robot1', context=spinning.context)) for i in instances]
    return nodes, reporter


def test_a_manager_that_subscribes_later_is_told_every_state_the_process_knows(spinning):
    instances = [{'instance': 'first', 'managed': True},
                 {'instance': 'refusing', 'managed': True},
                 {'instance': 'after_cpp', 'managed': True, 'after': ['cpp']},
                 {'instance': 'unmanaged', 'managed': False}]
    nodes, reporter = _process(spinning, instances, refusing={'refusing'})
    bring_up(instances, nodes, reporter)
    # the hidden node publishes only: no parameter services, no rosout
    assert reporter.node.get_fully_qualified_name() == f"/robot1/{reporter_name('tidy_system')}"
    assert not list(reporter.node.services)
    # latched: a manager that subscribes once it was published is told all the same
    manager = spinning.add(LifecycleNode('manager', context=spinning.context))
    reports = Reports(manager, DESCRIPTION, ['first', 'refusing', 'after_cpp', 'elsewhere'])
    start = time.monotonic()
    assert reports.take('first', _never) == 'active'
    assert time.monotonic() - start < 5
    # left where it is: unconfigured, what it comes after is not in the process
    assert reports.take('after_cpp', _never) == 'unconfigured'
    # failed there: not told, asked by the manager; and not waited for once all is told
    start = time.monotonic()
    assert reports.take('refusing', _never) is None
    assert reports.take('elsewhere', _never) is None
    assert time.monotonic() - start < 1
    # taken once: a later bring-up (after a bring-down, a respawn) asks the instance
    assert reports.take('first', _never) is None


def test_what_no_process_tells_is_not_waited_for_or_only_for_a_while(spinning):
    manager = spinning.add(LifecycleNode('manager', context=spinning.context))
    reports = Reports(manager, DESCRIPTION, ['shared'], grace=0.5)
    start = time.monotonic()
    assert reports.take('alone', _never) is None
    assert time.monotonic() - start < 0.2
    # a process that never tells (no --activate): asked after the grace
    assert reports.take('shared', _never) is None
    assert 0.4 < time.monotonic() - start < 3
    stopped = threading.Event()
    threading.Timer(0.3, stopped.set).start()
    start = time.monotonic()
    reports = Reports(manager, DESCRIPTION, ['shared'], grace=30)
    assert reports.take('shared', stopped.is_set) is None
    assert time.monotonic() - start < 3


def test_the_activation_takes_a_told_state_and_asks_what_was_not_told(spinning):
    # 'told' has no node at all: only its process's word makes it active; 'asked'
    # is a real node, brought up through its lifecycle services
    spinning.add(LifecycleNode('asked', namespace='/system', context=spinning.context))
    driver = spinning.add(LifecycleNode('driver', context=spinning.context))
    said = []
    activation = SystemActivation(
        driver, {'told': '/system/told', 'asked': '/system/asked'}, {'asked': ['told']},
        timeout=10.0, report=lambda level, text: said.append((level, text)),
        told=lambda name, stopped: 'active' if name == 'told' else None)
    activation.start()
    outcome = activation.wait(30)
    assert outcome.ok and outcome.active == ['asked', 'told'], (outcome, said)
    # its services are looked for in the background: not there, it is still discovering
    assert activation.discovering('told')
    assert not activation.discovering('asked')
