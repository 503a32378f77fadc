# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""The system manager serves on through a callback that raises, on real rclpy."""

import argparse
import threading
import time

from conftest import answer, wait_until
import rclpy
from rclpy.executors import MultiThreadedExecutor, SingleThreadedExecutor
from robmosys_runtime.hosting import output
from robmosys_runtime.hosting.output import guarded
from robmosys_runtime.system import manager
from robmosys_runtime.system.manager import serve
from std_srvs.srv import Trigger


class Served:
    """A node with services, spun by :func:`serve` in a thread, and a client node."""

    def __init__(self, context) -> None:
        self.node = rclpy.create_node('served', context=context)
        self.client_node = rclpy.create_node('asking', context=context)
        self.executor = MultiThreadedExecutor(num_threads=2, context=context)
        self.executor.add_node(self.node)
        self.asking = SingleThreadedExecutor(context=context)
        self.asking.add_node(self.client_node)
        self.thread = threading.Thread(target=serve, args=(self.executor,), daemon=True)

    def call(self, service: str, timeout: float = 10.0):
        """
        Call a Trigger service; return its response, None if none came in timeout.

        Asked again while no answer comes (see :func:`conftest.answer`).
        """
        client = self.client_node.create_client(Trigger, service)
        assert client.wait_for_service(timeout_sec=timeout)
        try:
            return answer(client, Trigger.Request(), timeout, self.asking)
        finally:
            self.client_node.destroy_client(client)


def _broken(request, response):
    raise KeyError('laser_spare')


def _fine(request, response):
    response.success = True
    response.message = 'fine'
    return response


def test_a_failing_service_is_answered_reported_and_the_others_serve_on(monkeypatch):
    said = []
    for module in (manager, output):  # guarded's and serve's
        monkeypatch.setattr(module, 'say', lambda level, text: said.append((level, text)))
    context = rclpy.Context()
    rclpy.init(context=context)
    served = Served(context)
    try:
        served.node.create_service(Trigger, 'guarded', guarded('report', _broken))
        # a callback nobody guarded: rclpy raises it out of spin, serve spins on
        served.node.create_service(Trigger, 'unguarded', _broken)
        served.node.create_service(Trigger, 'fine', _fine)
        served.thread.start()

        answer = served.call('guarded')
        assert answer is not None and not answer.success
        assert answer.message.startswith("report failed: KeyError: 'laser_spare' (at ")
        assert answer.message.endswith(f':{_broken.__code__.co_firstlineno + 1})')
        # no answer comes from a callback that raised, but the executor serves on
        assert served.call('unguarded', timeout=3.0) is None
        for _ in range(2):
            answer = served.call('fine')
            assert answer is not None and answer.success and answer.message == 'fine'
        assert served.thread.is_alive()
        assert said[0][0] == 'error'
        assert said[0][1].startswith("report failed: KeyError: 'laser_spare' (at ")
        assert any(text.startswith("a callback of the manager failed: KeyError: 'laser_spare'")
                   for _, text in said[1:])
    finally:
        served.executor.shutdown()
        served.asking.shutdown()
        served.node.destroy_node()
        served.client_node.destroy_node()
        rclpy.try_shutdown(context=context)
    served.thread.join(10)
    assert not served.thread.is_alive()


def test_a_failing_timer_callback_is_reported_once(monkeypatch):
    said = []
    for module in (manager, output):  # guarded's and serve's
        monkeypatch.setattr(module, 'say', lambda level, text: said.append((level, text)))
    calls = []

    def publish():
        calls.append(1)
        raise RuntimeError('no publisher')

    tick = guarded('publishing /diagnostics', publish)
    for _ in range(3):
        assert tick() is None
    assert len(calls) == 3
    assert [level for level, _ in said] == ['error']
    assert said[0][1].startswith('publishing /diagnostics failed: RuntimeError: no publisher')


def test_ros_arguments_are_left_out_as_rclpy_leaves_them_out():
    from rclpy.utilities import remove_ros_args
    from robmosys_runtime.tools.arguments import without_ros_args
    for argv in ([], ['--attach'],
                 ['--attach', '--ros-args', '-r', '__node:=x', '--log-level', 'warn'],
                 ['--ros-args', '-r', 'a:=b', '--', '--timeout', '3'],
                 ['--timeout', '3', '--ros-args', '-p', 'x:=1', '--', '--attach',
                  '--ros-args', '--log-level', 'debug'],
                 ['--', '--attach']):
        # rclpy takes the first argument for the program's name
        assert without_ros_args(argv) == remove_ros_args(['bringup', *argv])[1:], argv


def test_the_ros_arguments_are_the_manager_s_own_as_rcl_reads_them():
    from rclpy.utilities import remove_ros_args
    from robmosys_runtime.tools.arguments import ros_args_only
    argv = ['--timeout', '3', '--ros-args', '-r', '__node:=site', '--', '--attach',
            '--ros-args', '--log-level', 'debug']
    taken = ros_args_only(argv)
    assert taken == ['--ros-args', '-r', '__node:=site', '--ros-args', '--log-level', 'debug']
    # what rclpy would leave is the rest: nothing of the options
    assert remove_ros_args(['bringup', *taken]) == ['bringup']
    context = rclpy.Context()
    rclpy.init(context=context, args=['bringup', *taken, '--ros-args'])
    try:
        node = rclpy.create_node('x_bringup', context=context)
        helper = rclpy.create_node('x_bringup_watch', context=context, use_global_arguments=False)
        assert (node.get_name(), helper.get_name()) == ('site', 'x_bringup_watch')
        node.destroy_node()
        helper.destroy_node()
    finally:
        rclpy.try_shutdown(context=context)


def test_each_service_answers_from_the_moment_it_exists(monkeypatch):
    """The manager's node spins while the manager is made: no service sees it half made."""
    said = []
    for module in (manager, output):  # guarded's and serve's
        monkeypatch.setattr(module, 'say', lambda level, text: said.append((level, text)))
    context = rclpy.Context()
    rclpy.init(context=context)
    node = rclpy.create_node('system_bringup', context=context)
    answers = {}
    create_service = node.create_service

    def create_and_call(kind, name, callback, **kwargs):
        # a request that arrives as soon as the service is there
        service = create_service(kind, name, callback, **kwargs)
        answers[name] = callback(Trigger.Request(), Trigger.Response())
        return service
    monkeypatch.setattr(node, 'create_service', create_and_call)
    args = argparse.Namespace(
        attach=True, processes=None, description='', timeout=5.0, start_timeout=5.0,
        heartbeat=0.0, diagnostics_period=1.0, check_period=1.0, silence=5.0)
    description = {'package': 'system', 'namespace': '', 'instances': [], 'connections': []}
    try:
        made = manager.Manager(node, description, '', args)
        assert sorted(answers) == ['~/bring_down', '~/bring_up', '~/conformance', '~/report']
        assert [s for s in said if s[0] == 'error'] == [], said
        assert answers['~/report'].success, answers['~/report'].message
        assert not answers['~/conformance'].success
        assert answers['~/conformance'].message == \
            'the conformance watch starts once the system is up'
        # made once the bring-up (of nothing here) is over
        assert made.watch is None
        made.start()
        assert wait_until(lambda: made.watch is not None, 10)
        made.stopping.set()
    finally:
        node.destroy_node()
        rclpy.try_shutdown(context=context)


def test_the_watch_is_made_once_the_bring_up_is_over(monkeypatch):
    """Its node and subscriptions, made while the instances start, slowed them (issue 28)."""
    monkeypatch.setattr(manager, 'say', lambda level, text: None)
    context = rclpy.Context()
    rclpy.init(context=context)
    node = rclpy.create_node('late_bringup', context=context)
    args = argparse.Namespace(
        attach=True, processes=None, description='', timeout=2.0, start_timeout=2.0,
        heartbeat=0.0, diagnostics_period=1.0, check_period=1.0, silence=5.0)
    # an instance that never appears: its bring-up lasts the start timeout
    description = {'package': 'late', 'namespace': '', 'connections': [], 'instances': [
        {'instance': 'absent', 'fqn': '/absent', 'name': 'absent', 'namespace': '',
         'managed': True, 'after': []}]}
    try:
        made = manager.Manager(node, description, '', args)
        made.start()
        assert made.activation.running()
        time.sleep(1.0)
        assert made.watch is None
        assert wait_until(lambda: not made.activation.running(), 20)
        assert wait_until(lambda: made.watch is not None, 10)
        made.stopping.set()
    finally:
        node.destroy_node()
        rclpy.try_shutdown(context=context)
