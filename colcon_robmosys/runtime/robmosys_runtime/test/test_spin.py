# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""A component's process spins on through rclpy's race with destroyed entities."""

import threading

from conftest import wait_until
import rclpy
from rclpy.exceptions import InvalidHandle
from rclpy.executors import ExternalShutdownException, MultiThreadedExecutor
from rclpy.waitable import NumberOfEntities, Waitable
from robmosys_runtime.main import spin


class DestroyedWhileGathered(Waitable):
    """
    What a port destroyed by a transition looks like to the spinning thread, once.

    rclpy's executor marks a waitable in use, then adds it to its wait set; a
    port destroyed in between (its event handler) raises InvalidHandle there,
    out of spin (ros2/rclpy#1142, #1206). This one does so the first time.
    """

    def __init__(self, callback_group, error: Exception) -> None:
        super().__init__(callback_group)
        self.raised = threading.Event()
        self.error = error

    def __enter__(self) -> None:
        return None

    def __exit__(self, *exc_info) -> None:
        return None

    def is_ready(self, wait_set) -> bool:
        return False

    def take_data(self) -> None:
        return None

    async def execute(self, taken_data) -> None:
        return None

    def get_num_entities(self) -> NumberOfEntities:
        return NumberOfEntities()

    def add_to_wait_set(self, wait_set) -> None:
        if not self.raised.is_set():
            self.raised.set()
            raise self.error


#: What rclpy raises for an entity destroyed while the executor used it.
DESTROYED = InvalidHandle('cannot use Destroyable because destruction was requested')


def _spun(spinner, error: Exception = DESTROYED):
    """Spin a node with a 20 ms timer and the waitable above; return the ticks and the end."""
    context = rclpy.Context()
    rclpy.init(context=context)
    node = rclpy.create_node('spun', context=context)
    ticks = []
    node.create_timer(0.02, lambda: ticks.append(1))
    waitable = DestroyedWhileGathered(node.default_callback_group, error)
    node.add_waitable(waitable)
    executor = MultiThreadedExecutor(num_threads=2, context=context)
    executor.add_node(node)
    thread, ended = _spin_in_thread(spinner, executor)
    try:
        assert waitable.raised.wait(10)
        # the timer goes on ticking, or the spinning ended with the race
        wait_until(lambda: len(ticks) >= 5 or ended, timeout=10)
        return len(ticks), ended
    finally:
        executor.shutdown()
        node.destroy_node()
        rclpy.try_shutdown(context=context)
        thread.join(10)


def test_spin_goes_on_through_an_entity_destroyed_while_gathered():
    ticks, ended = _spun(spin)
    assert ticks >= 5 and not ended


def test_spin_goes_on_through_an_action_server_released_with_a_request_taken():
    # rcl_action's words, raised by rclpy out of spin (once in CI: a test's event
    # server released while the executor held the cancel request of its client)
    ticks, ended = _spun(spin, RuntimeError(
        'Failed to process cancel request: action server pointer is invalid, '
        'at /project/src/rcl_action/action_server.c:1020'))
    assert ticks >= 5 and not ended


def test_spin_ends_on_any_other_error():
    ticks, ended = _spun(spin, RuntimeError('something else'))
    assert ended and ticks < 5


def test_rclpy_alone_ends_spinning_there():
    # what spin() is for: without it, the process ended with all its nodes
    ticks, ended = _spun(lambda executor: executor.spin())
    assert ended and ticks < 5


def _served_on_events(spinner):
    """
    Serve a request on rclpy's EventsExecutor by a service that its own callback destroys.

    That is a request answered after a cleanup destroyed its port, made certain:
    rclpy's EventsExecutor holds the service, and its send_response raises
    InvalidHandle out of spin. Return the ticks of a 20 ms timer after it and the end.
    """
    from rclpy.experimental import EventsExecutor
    from std_srvs.srv import Empty
    context = rclpy.Context()
    rclpy.init(context=context)
    node = rclpy.create_node('served', context=context)
    ticks = []
    answered = threading.Event()

    def answer(request, response):
        node.destroy_service(service)
        answered.set()
        return response
    service = node.create_service(Empty, 'ask_once', answer)
    executor = EventsExecutor(context=context)
    executor.add_node(node)
    thread, ended = _spin_in_thread(spinner, executor)
    asking = rclpy.Context()
    rclpy.init(context=asking)
    asker = rclpy.create_node('asker', context=asking)
    try:
        client = asker.create_client(Empty, '/ask_once')
        assert client.wait_for_service(timeout_sec=20)
        client.call_async(Empty.Request())
        assert answered.wait(20)
        node.create_timer(0.02, lambda: ticks.append(1))
        wait_until(lambda: len(ticks) >= 5 or ended, timeout=10)
        return len(ticks), ended
    finally:
        asker.destroy_node()
        rclpy.try_shutdown(context=asking)
        rclpy.try_shutdown(context=context)
        executor.shutdown()
        thread.join(10)
        node.destroy_node()


def test_spin_on_events_goes_on_through_a_request_to_a_destroyed_service():
    ticks, ended = _served_on_events(spin)
    assert ticks >= 5 and not ended


def test_rclpy_events_executor_alone_ends_spinning_there():
    from robmosys_runtime.main import EVENTS_SPIN_PERIOD
    ticks, ended = _served_on_events(
        lambda executor: executor.spin_until_future_complete(
            rclpy.task.Future(), timeout_sec=EVENTS_SPIN_PERIOD))
    assert ended and ticks < 5


def test_a_process_has_the_threads_its_nodes_need(monkeypatch):
    import os
    from types import SimpleNamespace

    from robmosys_runtime.executors import DEFAULT_MIN_THREADS, executor_threads
    monkeypatch.setattr(os, 'cpu_count', lambda: 2)
    # a generated node states what it needs: its callback groups and one more
    assert executor_threads([SimpleNamespace(min_threads=3)]) == 3
    # the nodes of a shared process add up
    assert executor_threads([SimpleNamespace(min_threads=3)] * 5) == 15
    # never fewer threads than CPUs, what a hand-written rclpy node spins with
    assert executor_threads([SimpleNamespace(min_threads=1)]) == 2
    # a node that does not say gets threads to spare
    assert executor_threads([object()]) == DEFAULT_MIN_THREADS
    monkeypatch.setattr(os, 'cpu_count', lambda: 16)
    assert executor_threads([SimpleNamespace(min_threads=3)]) == 16


def test_a_process_spins_on_the_executor_its_nodes_need():
    from types import SimpleNamespace

    import pytest
    from rclpy.executors import MultiThreadedExecutor, SingleThreadedExecutor
    from robmosys_runtime.executors import executor_kind, make_executor, ThreadsExecutor

    events, single, multi = (SimpleNamespace(executor_name=name) for name in (
        'events', 'single-threaded', 'multi-threaded'))
    assert executor_kind([events]) == 'events'
    # nodes of one process: the most capable executor one of them needs
    assert executor_kind([events, single]) == 'single-threaded'
    assert executor_kind([events, multi, single]) == 'multi-threaded'
    # a node that does not say (written by hand) keeps the multi-threaded one
    assert executor_kind([events, object()]) == 'multi-threaded'
    # the system's choice wins; a name nobody knows is refused
    assert executor_kind([multi], 'events') == 'events'
    with pytest.raises(ValueError):
        executor_kind([events], 'fast')
    rclpy.init()
    try:
        assert isinstance(make_executor('single-threaded'), SingleThreadedExecutor)
        assert isinstance(make_executor('multi-threaded', [multi]), MultiThreadedExecutor)
        assert isinstance(make_executor('multi-threaded', [multi]), ThreadsExecutor)
    finally:
        rclpy.try_shutdown()


def test_an_events_executor_runs_timers_and_ends_with_its_context():
    from rclpy.experimental import EventsExecutor

    context = rclpy.Context()
    rclpy.init(context=context)
    executor = EventsExecutor(context=context)
    node = rclpy.create_node('ticking', context=context)
    ticks = []
    node.create_timer(0.01, lambda: ticks.append(1))
    executor.add_node(node)
    ended = []

    def spin_until_shutdown() -> None:
        try:
            spin(executor)
        except ExternalShutdownException:
            ended.append(True)  # what the process's run_nodes takes as the end
    spinning = threading.Thread(target=spin_until_shutdown, daemon=True)
    spinning.start()
    try:
        assert wait_until(lambda: len(ticks) >= 5, 10)
    finally:
        rclpy.try_shutdown(context=context)
        spinning.join(10)
    assert not spinning.is_alive() and ended
    node.destroy_node()


def _spin_in_thread(spinner, executor):
    """Spin executor with spinner in a thread; return it and the error that ended it."""
    ended = []

    def run():
        try:
            spinner(executor)
        except (InvalidHandle, RuntimeError) as error:
            ended.append(error)

    thread = threading.Thread(target=run, daemon=True)
    thread.start()
    return thread, ended


def test_a_timer_cancelled_after_the_wait_is_skipped_and_its_group_served_on():
    from robmosys_runtime.executors import ThreadsExecutor

    context = rclpy.Context()
    rclpy.init(context=context)
    node = rclpy.create_node('deactivated', context=context)
    executor = ThreadsExecutor(num_threads=2, context=context)
    try:
        ran = []
        timer = node.create_timer(0.001, lambda: ran.append('activity'))
        executor.add_node(node)
        # the spinning thread finds the timer ready; a deactivation cancels it
        # before it is taken, as another of the executor's threads does
        handler, entity, _ = executor.wait_for_ready_callbacks(timeout_sec=5.0)
        assert entity is timer
        timer.cancel()
        handler()
        assert handler.exception() is None and ran == []
        # the node's default group is free again: its other callbacks run
        node.create_timer(0.001, lambda: ran.append('next'))
        assert wait_until(lambda: (executor.spin_once(timeout_sec=0.05), 'next' in ran)[1],
                          5)
    finally:
        executor.shutdown()
        node.destroy_node()
        rclpy.try_shutdown(context=context)
