# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""QueryClient and ActionClientPort against real rclpy servers."""

import threading
import time

from conftest import wait_until
import pytest
import rclpy
from rclpy.executors import MultiThreadedExecutor
from rclpy.node import Node
from robmosys_runtime import ActionClientPort, QueryClient
from robmosys_runtime.ports import ActionClient, ActionServer
from test_msgs.action import Fibonacci
from test_msgs.srv import BasicTypes


def _serve(spinning):
    server = spinning.add(Node('server', context=spinning.context))

    def answer(request, response):
        response.int32_value = request.int32_value + 1000
        return response
    server.create_service(BasicTypes, 'add', answer)

    def execute(goal_handle):
        sequence = [0, 1]
        for _ in range(goal_handle.request.order - 1):
            sequence.append(sequence[-1] + sequence[-2])
            goal_handle.publish_feedback(Fibonacci.Feedback(sequence=sequence))
        if goal_handle.request.order < 0:
            goal_handle.abort()
        else:
            goal_handle.succeed()
        return Fibonacci.Result(sequence=sequence)
    ActionServer(server, Fibonacci, 'fibonacci', execute)
    return server


def test_query_client_blocking_and_asynchronous(spinning):
    _serve(spinning)
    client_node = spinning.add(Node('client', context=spinning.context))
    answers = []
    client = QueryClient(client_node, BasicTypes, 'add', answers.append)
    assert client.wait_for_service(timeout_sec=10)
    # asked again while rmw_fastrtps drops the answer to a reader the server has
    # not matched yet; once one came, the server has it and none is dropped
    for attempt in (1.0, 2.0, 4.0, 8.0):
        try:
            answered = client.call(BasicTypes.Request(int32_value=5), timeout_sec=attempt)
            break
        except TimeoutError:
            assert attempt < 8.0
    assert answered.int32_value == 1005
    client.call_async(BasicTypes.Request(int32_value=7))
    assert wait_until(lambda: answers)
    assert answers[0].int32_value == 1007
    client.destroy()


def test_a_goal_accepted_while_the_port_is_released_ends_quietly(spinning):
    # the acceptance of a goal sent asynchronously can come while a cleanup
    # releases the port, in another thread: asking the client that is gone for
    # the result raised in the executor, which ended the process (seen on
    # Jazzy, a shared process of eight instances); made deterministic
    _serve(spinning)
    client_node = spinning.add(Node('client', context=spinning.context))
    results = []
    client = ActionClientPort(client_node, Fibonacci, 'fibonacci', results.append)
    assert client.wait_for_server(timeout_sec=10)
    accepted = client.client.send_goal_async(Fibonacci.Goal(order=2))
    assert wait_until(accepted.done)
    assert accepted.result().accepted
    client.destroy()
    # the executor lets go of the client's handle at its next wake: rclpy then
    # destroys it, as it did under the late acceptance
    spinning.executor.wake()
    time.sleep(0.5)
    client._accepted(accepted)  # the acceptance's callback, after the release
    assert results == []


def test_query_client_times_out_without_server(spinning):
    client_node = spinning.add(Node('client', context=spinning.context))
    client = QueryClient(client_node, BasicTypes, 'nobody')
    with pytest.raises(TimeoutError, match='no server of nobody'):
        client.call(BasicTypes.Request(), timeout_sec=0.2)


def test_action_client_blocking_asynchronous_and_feedback(spinning):
    _serve(spinning)
    client_node = spinning.add(Node('client', context=spinning.context))
    results, feedback = [], []
    client = ActionClientPort(client_node, Fibonacci, 'fibonacci', results.append)
    assert client.wait_for_server(timeout_sec=10)
    result = client.send_goal(Fibonacci.Goal(order=5),
                              feedback_callback=lambda m: feedback.append(m))
    assert list(result.sequence) == [0, 1, 1, 2, 3, 5]
    assert feedback
    client.send_goal_async(Fibonacci.Goal(order=3))
    assert wait_until(lambda: results)
    assert list(results[0].sequence) == [0, 1, 1, 2]
    client.destroy()


def test_blocking_calls_from_a_callback_of_the_executor(spinning):
    """A blocking call inside a callback is answered by another thread of the executor."""
    _serve(spinning)
    client_node = spinning.add(Node('caller', context=spinning.context))
    client = QueryClient(client_node, BasicTypes, 'add')
    got = []
    done = threading.Event()

    def tick():
        timer.cancel()
        got.append(client.call(BasicTypes.Request(int32_value=1)).int32_value)
        done.set()
    timer = client_node.create_timer(0.05, tick)
    assert done.wait(10)
    assert got == [1001]


@pytest.mark.parametrize('make', ['ActionClient', 'ActionClientPort', 'ActionServer'])
def test_action_entities_made_and_destroyed_while_the_executor_spins_their_node(make):
    # ports are made in on_configure, on an executor thread, while other
    # threads of the executor build their wait sets from the node's waitables
    # (ros2/rclpy#1589: rclpy's client joins them before it has its lock), and
    # destroyed on cleanup the same way (rclpy destroys before it removes)
    context = rclpy.Context()
    rclpy.init(context=context)
    executor = MultiThreadedExecutor(num_threads=4, context=context)
    node = Node('maker', context=context)
    # a timer keeps the executor threads rebuilding their wait sets
    node.create_timer(0.0001, lambda: None)
    executor.add_node(node)
    failures = []

    def spin():
        try:
            executor.spin()
        except Exception as failure:  # noqa: B902 - what the test looks for
            if context.ok():
                failures.append(failure)
    thread = threading.Thread(target=spin, daemon=True)
    thread.start()
    try:
        for index in range(150):
            if make == 'ActionClient':
                client = ActionClient(node, Fibonacci, f'fibonacci_{index}')
                client.destroy()
            elif make == 'ActionServer':
                ActionServer(node, Fibonacci, f'fibonacci_{index}', lambda goal: None).destroy()
            else:
                ActionClientPort(node, Fibonacci, f'fibonacci_{index}').destroy()
            assert not failures, failures
    finally:
        executor.shutdown()
        node.destroy_node()
        rclpy.try_shutdown(context=context)
        thread.join(10)
    assert not failures, failures
