# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""What the shared process tells the manager it brought up, on real rclpy (reports.py)."""

import json
import os
import subprocess
import sys
import threading
import time

from rclpy.lifecycle import Node as LifecycleNode
from rclpy.lifecycle import TransitionCallbackReturn
from robmosys_runtime.hosting.container import bring_up
from robmosys_runtime.hosting.reports import Reporter, reporter_name, Reports
from robmosys_runtime.hosting.told import (
    bringing_itself_down, read_told, read_told_file, tellers, tells_all, told_file)
from robmosys_runtime.system.activation import SystemActivation

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


def test_closing_waits_for_the_clients_made_in_the_background(spinning, monkeypatch):
    # every instance told: their clients are made one by one once the bring-up is
    # over; the system shuts down meanwhile (Ctrl-C right after the report), and
    # the node goes right after close(): no client is made on it then
    driver = LifecycleNode('driver', context=spinning.context)
    names = {f'told_{i}': f'/system/told_{i}' for i in range(300)}
    activation = SystemActivation(driver, names, {}, timeout=10.0,
                                  told=lambda name, stopped: 'active')
    failures = []
    monkeypatch.setattr(threading, 'excepthook', failures.append)
    activation.start()
    assert activation.wait(30).ok
    activation.close()
    driver.destroy_node()
    time.sleep(0.5)
    assert failures == []


def test_the_states_go_to_the_pipe_of_bringup_too_and_it_is_closed(spinning):
    instances = [{'instance': 'first', 'managed': True},
                 {'instance': 'refusing', 'managed': True},
                 {'instance': 'after_refusing', 'managed': True, 'after': ['refusing']}]
    nodes, reporter = _process(spinning, instances, refusing={'refusing'})
    reading, writing = os.pipe()
    bring_up(instances, nodes, reporter, writing)
    told = read_told([reading], 5.0, threading.Event())
    assert told == {'first': 'active', 'after_refusing': 'unconfigured'}
    # both ends are closed: the process's by bring_up, bringup's by read_told
    for fd in (reading, writing):
        try:
            os.fstat(fd)
        except OSError:
            continue
        raise AssertionError(f'file descriptor {fd} is still open')
    # and a manager made afterwards takes them as told, at once
    manager = spinning.add(LifecycleNode('manager', context=spinning.context))
    reports = Reports(manager, DESCRIPTION, ['first', 'refusing', 'after_refusing'])
    reports.told(told)
    start = time.monotonic()
    assert reports.take('first', _never) == 'active'
    assert reports.take('after_refusing', _never) == 'unconfigured'
    assert reports.take('refusing', _never) is None
    assert time.monotonic() - start < 0.5


def test_a_pipe_that_says_nothing_leaves_the_states_to_the_manager():
    # the process ended before it wrote (end of file)
    reading, writing = os.pipe()
    os.close(writing)
    assert read_told([reading], 5.0, threading.Event()) is None
    # it wrote something else than the states
    reading, writing = os.pipe()
    os.write(writing, b'["first"]\n')
    assert read_told([reading], 5.0, threading.Event()) is None
    os.close(writing)
    # nothing within the timeout, or a signal came: no longer waited for
    for timeout, signalled in ((0.3, threading.Event()), (30.0, threading.Event())):
        reading, writing = os.pipe()
        if timeout > 1:
            threading.Timer(0.3, signalled.set).start()
        start = time.monotonic()
        assert read_told([reading], timeout, signalled) is None
        assert time.monotonic() - start < 3
        os.close(writing)
    # a line written in pieces is read whole
    reading, writing = os.pipe()
    text = json.dumps({'first': 'active'}).encode() + b'\n'
    os.write(writing, text[:5])
    threading.Timer(0.2, lambda: os.write(writing, text[5:])).start()
    assert read_told([reading], 5.0, threading.Event()) == {'first': 'active'}
    os.close(writing)


def test_bringup_reads_the_pipe_only_where_the_shared_process_brings_up_every_managed():
    def system(*instances, processes='shared'):
        return {'processes': processes, 'instances': [
            dict({'managed': True, 'python_class': 'pkg.mod:Class'}, **i) for i in instances]}
    assert tells_all(system({'instance': 'a'}, {'instance': 'b'}), None)
    # an unmanaged instance elsewhere does not matter
    assert tells_all(system({'instance': 'a'}, {'instance': 'b', 'managed': False,
                                                'python_class': None, 'plugin': 'x'}), None)
    # the C++ component container tells too: both together tell all
    both = system({'instance': 'a'}, {'instance': 'b', 'python_class': None, 'plugin': 'x'})
    assert tells_all(both, None)
    assert tellers(both, None) == {'python instances': ['a'], 'C++ instances': ['b']}
    assert tellers(system({'instance': 'a'}), None) == {'python instances': ['a']}
    # one per instance; another host; an instance run by a command
    assert not tells_all(system({'instance': 'a'}, processes='per-instance'), None)
    assert not tells_all(system({'instance': 'a'}), False)
    assert not tells_all(both, False)
    assert not tells_all(system({'instance': 'a'}, {'instance': 'b', 'host': 'arm'}), None)
    assert not tells_all(system({'instance': 'a'}, {'instance': 'b', 'command': ['x']}), None)
    # nothing managed: nothing to tell
    assert not tells_all(system({'instance': 'a', 'managed': False}), None)
    # the process that holds every managed instance brings them down itself,
    # the Python one or the C++ container; none where they are split
    cpp = {'python_class': None, 'plugin': 'x'}
    assert bringing_itself_down(system({'instance': 'a'}, {'instance': 'b'}), None) == \
        'python instances'
    assert bringing_itself_down(system(dict(cpp, instance='a'), dict(cpp, instance='b'),
                                       {'instance': 'c', 'managed': False}), None) == \
        'C++ instances'
    assert bringing_itself_down(both, None) is None
    assert bringing_itself_down(system({'instance': 'a'}), False) is None
    assert bringing_itself_down(system({'instance': 'a', 'managed': False}), None) is None


def test_the_states_go_to_the_file_of_the_launch_too(spinning, tmp_path):
    instances = [{'instance': 'first', 'managed': True}]
    nodes, reporter = _process(spinning, instances)
    told = tmp_path / 'brought_up.json'
    bring_up(instances, nodes, reporter, report_file=str(told))
    assert read_told_file([str(told)], 5.0, threading.Event()) == {'first': 'active'}
    # written whole: no temporary file is left beside it
    assert sorted(p.name for p in tmp_path.iterdir()) == ['brought_up.json']


def test_the_file_is_waited_for_while_its_process_lives(tmp_path):
    told = tmp_path / 'brought_up.json'
    # a process that started and ended without writing it: not waited for
    ended = subprocess.run([sys.executable, '-c', 'import os; print(os.getpid())'],
                           capture_output=True, text=True, check=True)
    (tmp_path / 'brought_up.json.started').write_text(ended.stdout.strip())
    start = time.monotonic()
    assert read_told_file([str(told)], 30.0, threading.Event()) is None
    assert time.monotonic() - start < 3
    # one that lives writes it later: read once whole
    (tmp_path / 'brought_up.json.started').write_text(str(os.getpid()))
    threading.Timer(0.5, lambda: told.write_text('{"first": "active"}\n')).start()
    start = time.monotonic()
    assert read_told_file([str(told)], 30.0, threading.Event()) == {'first': 'active'}
    assert 0.3 < time.monotonic() - start < 5
    # nothing started: waited for until the timeout, or a signal
    told.unlink()
    (tmp_path / 'brought_up.json.started').unlink()
    start = time.monotonic()
    assert read_told_file([str(told)], 0.5, threading.Event()) is None
    assert 0.4 < time.monotonic() - start < 3
    signalled = threading.Event()
    threading.Timer(0.3, signalled.set).start()
    assert read_told_file([str(told)], 30.0, signalled) is None
    assert time.monotonic() - start < 5


def test_two_processes_tell_through_pipes_and_files_of_their_own():
    # the shared Python process and the C++ container, each on its pipe
    python, python_writing = os.pipe()
    cpp, cpp_writing = os.pipe()
    os.write(python_writing, b'{"talker": "active"}\n')
    threading.Timer(0.3, lambda: os.write(cpp_writing, b'{"listener": "active"}\n')).start()
    assert read_told([python, cpp], 5.0, threading.Event()) == {
        'talker': 'active', 'listener': 'active'}
    os.close(python_writing)
    os.close(cpp_writing)
    # one ended without writing: the other's states are taken, the rest asked
    python, python_writing = os.pipe()
    cpp, cpp_writing = os.pipe()
    os.close(cpp_writing)
    os.write(python_writing, b'{"talker": "active"}\n')
    assert read_told([python, cpp], 5.0, threading.Event()) == {'talker': 'active'}
    os.close(python_writing)


def test_the_cpp_container_tells_in_a_file_beside_the_launch_s(tmp_path):
    told = str(tmp_path / 'brought_up.json')
    assert told_file(told, 'python instances') == told
    assert told_file(told, 'C++ instances') == told + '.cpp'
    (tmp_path / 'brought_up.json').write_text('{"talker": "active"}\n')
    threading.Timer(0.3, lambda: (tmp_path / 'brought_up.json.cpp').write_text(
        '{"listener": "unconfigured"}\n')).start()
    assert read_told_file([told, told + '.cpp'], 5.0, threading.Event()) == {
        'talker': 'active', 'listener': 'unconfigured'}


def test_what_the_cpp_container_told_is_taken_though_no_topic_was_expected(spinning):
    manager = spinning.add(LifecycleNode('manager', context=spinning.context))
    # the manager expects a topic only of the Python process (here: none)
    reports = Reports(manager, DESCRIPTION, [])
    reports.told({'listener': 'active'})
    assert reports.take('listener', _never) == 'active'
    # taken once: a later bring-up asks the instance
    assert reports.take('listener', _never) is None
