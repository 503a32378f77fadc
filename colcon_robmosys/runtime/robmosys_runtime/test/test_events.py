# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""EventServer and EventClient over a real ROS 2 action (test_msgs/Fibonacci as the event)."""

import time

from conftest import wait_until
import pytest
from rclpy.node import Node
from rclpy.task import Future
from robmosys_runtime import EventClient, EventServer
from test_msgs.action import Fibonacci


def _pair(spinning, active=None, condition=None):
    server_node = spinning.add(Node('sensor', context=spinning.context))
    client_node = spinning.add(Node('watcher', context=spinning.context))
    server = EventServer(server_node, Fibonacci, 'event', active=active, condition=condition)
    events = []
    client = EventClient(client_node, Fibonacci, 'event', on_event=events.append)
    assert client.wait_for_server(timeout_sec=10)
    return server, client, events


def _event(value):
    return Fibonacci.Feedback(sequence=[value])


def test_events_reach_the_activations_whose_condition_holds(spinning):
    server, client, events = _pair(
        spinning, condition=lambda activation, event: event.sequence[0] >= activation.order)
    high = client.activate(Fibonacci.Goal(order=10))
    assert wait_until(lambda: server.activations == 1)
    assert wait_until(lambda: high.goal_handle is not None)
    assert server.fire(_event(3)) == 0
    assert server.fire(_event(12)) == 1
    assert wait_until(lambda: high.events == 1)
    assert [list(e.sequence) for e in events] == [[12]]
    client.deactivate(high)
    assert high.ended
    assert wait_until(lambda: server.activations == 0)
    assert server.fire(_event(20)) == 0
    client.destroy()
    server.destroy()


def test_an_inactive_server_refuses_activations(spinning):
    server, client, events = _pair(spinning, active=lambda: False)
    refused = client.activate(Fibonacci.Goal(order=1))
    assert wait_until(lambda: refused.ended)
    assert server.activations == 0
    assert refused.events == 0


def test_a_failing_condition_does_not_hold(spinning):
    def broken(activation, event):
        raise RuntimeError('broken condition')
    server, client, events = _pair(spinning, condition=broken)
    client.activate(Fibonacci.Goal(order=1))
    assert wait_until(lambda: server.activations == 1)
    assert server.fire(_event(1)) == 0
    assert events == []


def test_single_needs_a_single_field(spinning):
    server, client, events = _pair(spinning)
    with pytest.raises(ValueError, match='no single field'):
        client.activate(Fibonacci.Goal(order=1), single=True)


def test_an_activation_accepted_while_the_port_is_released_ends_quietly(spinning):
    # the answer to an activation can come while a cleanup releases the port,
    # in another thread: the port, deactivated, then cancels it on a client
    # that is gone (rclpy raised, which ended the process); made deterministic
    server, client, events = _pair(spinning)
    handle = client.activate(Fibonacci.Goal(order=1))
    assert wait_until(lambda: handle.goal_handle is not None)
    answered = Future()
    answered.set_result(handle.goal_handle)
    client.destroy()
    assert handle.ended
    # the executor lets go of the client's handle at its next wake: rclpy then
    # destroys it, as it did under the late answer
    spinning.executor.wake()
    time.sleep(0.5)
    client._accepted(handle, answered)  # the answer's callback, after the release
    server.destroy()


def test_destroying_the_server_ends_the_activations(spinning):
    server, client, events = _pair(spinning)
    handle = client.activate(Fibonacci.Goal(order=1))
    assert wait_until(lambda: server.activations == 1)
    server.destroy()
    assert wait_until(lambda: handle.ended)


def test_an_activation_its_server_ended_is_ended_without_its_result(spinning):
    server, client, events = _pair(spinning)
    # the result lost: rmw_fastrtps drops an answer whose client it has not matched
    # within 100 ms, as it did under load to a server destroyed right after the abort
    client._finished = lambda handle, future: None
    handle = client.activate(Fibonacci.Goal(order=1))
    assert wait_until(lambda: server.activations == 1)
    server.destroy()
    # the goal's status tells it
    assert wait_until(lambda: handle.ended)
    assert not handle.finished


def test_an_activation_made_before_the_server_is_there_is_sent_once_it_is(spinning):
    # a goal sent to no server is lost: so would be every event of its activation. The
    # name is this test's own: the graph may still show the servers of the tests before
    client_node = spinning.add(Node('watcher', context=spinning.context))
    events = []
    client = EventClient(client_node, Fibonacci, 'late_event', on_event=events.append)
    early = client.activate(Fibonacci.Goal(order=10))
    dropped = client.activate(Fibonacci.Goal(order=1))
    client.deactivate(dropped)  # deactivated while it waited: never sent
    time.sleep(0.5)
    assert early.goal_handle is None and not early.ended
    server_node = spinning.add(Node('sensor', context=spinning.context))
    server = EventServer(server_node, Fibonacci, 'late_event',
                         condition=lambda activation, event: event.sequence[0] >= activation.order)
    # the activation reaches the server (its answer may not come back: rmw_fastrtps
    # drops the response to a client whose reader the server has not matched yet)
    assert wait_until(lambda: server.activations == 1)
    time.sleep(0.5)
    assert server.activations == 1  # the one that waited, not the dropped one

    def fired() -> bool:
        # the events of a sensor keep coming: one that went out before the server's
        # publisher had matched the client's subscription is not the last
        server.fire(_event(12))
        return early.events >= 1
    assert wait_until(fired)
    assert {tuple(e.sequence) for e in events} == {(12,)}
    assert dropped.goal_handle is None and dropped.events == 0
    # once the server is there, an activation goes at once: no timer is left
    assert client._waiting_timer is None
    client.destroy()
    server.destroy()


def test_destroying_the_client_while_activations_wait_sends_nothing(spinning):
    client_node = spinning.add(Node('watcher', context=spinning.context))
    client = EventClient(client_node, Fibonacci, 'gone_event')
    waiting = client.activate(Fibonacci.Goal(order=1))
    client.destroy()
    assert waiting.ended
    server_node = spinning.add(Node('sensor', context=spinning.context))
    server = EventServer(server_node, Fibonacci, 'gone_event')
    time.sleep(1.0)
    assert server.activations == 0
    server.destroy()
