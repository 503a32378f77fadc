# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""The client ports of the query and action patterns: blocking and asynchronous calls."""

from __future__ import annotations

import threading
import time
from typing import Any, Callable, Optional

from rclpy.action import ActionClient as _RclpyActionClient
from rclpy.action import ActionServer as _RclpyActionServer
from rclpy.callback_groups import MutuallyExclusiveCallbackGroup
from rclpy.exceptions import InvalidHandle
from rclpy.node import Node
from rclpy.task import Future


def wait_for(future: Future, deadline: float, what: str) -> Any:
    """
    Return the result of a future; raise TimeoutError after the deadline.

    Safe from a callback of a multi-threaded executor: the future is completed
    by another thread, this one only waits.
    """
    done = threading.Event()
    future.add_done_callback(lambda _: done.set())
    if not done.wait(max(0.0, deadline - time.monotonic())):
        raise TimeoutError(f'{what} did not come in time')
    return future.result()


class QueryClient:
    """
    The client of a query port: a blocking and an asynchronous call.

    The client has a callback group of its own: a blocking call made from an
    activity is answered by another thread of the multi-threaded executor.
    """

    def __init__(self, node: Node, srv_type: Any, name: str,
                 on_answer: Optional[Callable[[Any], None]] = None) -> None:
        self._node = node
        self.name = name
        self.callback_group = MutuallyExclusiveCallbackGroup()
        self.client: Any = node.create_client(
            srv_type, name, callback_group=self.callback_group)
        self._on_answer = on_answer

    def wait_for_service(self, timeout_sec: Optional[float] = None) -> bool:
        """Wait until a server is there; return whether it is."""
        return self.client.wait_for_service(timeout_sec=timeout_sec)

    def call(self, request: Any, timeout_sec: float = 5.0) -> Any:
        """Return the answer to a request; raise TimeoutError if none comes in time."""
        deadline = time.monotonic() + timeout_sec
        if not self.client.wait_for_service(timeout_sec=timeout_sec):
            raise TimeoutError(f'no server of {self.name} within {timeout_sec} s')
        future = self.client.call_async(request)
        try:
            return wait_for(future, deadline, f'the answer on {self.name}')
        except TimeoutError:
            self.client.remove_pending_request(future)
            raise

    def call_async(self, request: Any) -> Future:
        """Send a request; its answer runs the activity the port triggers."""
        future = self.client.call_async(request)
        future.add_done_callback(self._answered)
        return future

    def _answered(self, future: Future) -> None:
        if self._on_answer is not None and not future.cancelled() and \
                future.exception() is None:
            self._on_answer(future.result())

    def destroy(self) -> None:
        """Release the client."""
        self._node.destroy_client(self.client)


def _unless_destroyed(handle: Any, call: Callable[[], Any], otherwise: Any) -> Any:
    """
    Return call() on an action entity in a wait set, or otherwise once it is destroyed.

    rclpy destroys an action client or server before it takes it out of its
    node's waitables, and an executor thread that listed the waitables in
    between adds the destroyed entity to its wait set and asks whether it is
    ready anyway ("action client pointer is invalid", rclpy 9.1 and 7.1).
    Ports are destroyed on cleanup while the executor spins. Such an entity
    was not counted in the wait set either, so leaving it out is right; and
    what it has to take is nothing (an empty dict: its execute does nothing).
    """
    try:
        with handle:
            return call()
    except InvalidHandle:
        return otherwise


class ActionClient(_RclpyActionClient):
    """
    rclpy's action client, safe to create and destroy while its node spins.

    rclpy (9.1 and 7.1 at least) adds an action client to its node before it
    creates the lock that ``get_num_entities`` takes (ros2/rclpy#1589): an
    executor thread that builds its wait set in that moment raises
    AttributeError, and the process ends. Ports are created in on_configure,
    on an executor thread, so the lock is made first here and kept.
    """

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        self.__dict__['_lock'] = threading.Lock()
        super().__init__(*args, **kwargs)

    def __setattr__(self, name: str, value: Any) -> None:
        if name == '_lock' and '_lock' in self.__dict__:
            # rclpy's own lock comes once the client is in the wait sets;
            # another thread may hold the first one already
            return
        super().__setattr__(name, value)

    def add_to_wait_set(self, wait_set: Any) -> None:
        """Add the client to a wait set, unless it is being destroyed."""
        _unless_destroyed(self._client_handle,
                          lambda: super(ActionClient, self).add_to_wait_set(wait_set), None)

    def is_ready(self, wait_set: Any) -> bool:
        """Return whether the client has something to take; never once destroyed."""
        return _unless_destroyed(self._client_handle,
                                 lambda: super(ActionClient, self).is_ready(wait_set), False)

    def take_data(self) -> Any:
        """Take what is ready; nothing once destroyed (the executor takes it unguarded)."""
        return _unless_destroyed(self._client_handle,
                                 lambda: super(ActionClient, self).take_data(), {})


class ActionServer(_RclpyActionServer):
    """rclpy's action server, safe to destroy while its node spins."""

    def add_to_wait_set(self, wait_set: Any) -> None:
        """Add the server to a wait set, unless it is being destroyed."""
        _unless_destroyed(self._handle,
                          lambda: super(ActionServer, self).add_to_wait_set(wait_set), None)

    def is_ready(self, wait_set: Any) -> bool:
        """Return whether the server has something to take; never once destroyed."""
        return _unless_destroyed(self._handle,
                                 lambda: super(ActionServer, self).is_ready(wait_set), False)

    def take_data(self) -> Any:
        """Take what is ready; nothing once destroyed (the executor takes it unguarded)."""
        return _unless_destroyed(self._handle,
                                 lambda: super(ActionServer, self).take_data(), {})


class ActionClientPort:
    """
    The client of an action port: goals sent asynchronously or blocking.

    The client has a callback group of its own, so that a blocking goal sent
    from an activity cannot block its own feedback and result.
    """

    def __init__(self, node: Node, action_type: Any, name: str,
                 on_result: Optional[Callable[[Any], None]] = None) -> None:
        self._node = node
        self.name = name
        self.callback_group = MutuallyExclusiveCallbackGroup()
        self.client: Any = ActionClient(
            node, action_type, name, callback_group=self.callback_group)
        self._on_result = on_result

    def wait_for_server(self, timeout_sec: Optional[float] = None) -> bool:
        """Wait until an action server is there; return whether it is."""
        return self.client.wait_for_server(timeout_sec=timeout_sec)

    def send_goal_async(self, goal: Any,
                        feedback_callback: Optional[Callable[[Any], None]] = None) -> Future:
        """
        Send a goal; its result runs the activity the port triggers.

        Return the future of the goal handle.
        """
        future = self.client.send_goal_async(goal, feedback_callback=feedback_callback)
        future.add_done_callback(self._accepted)
        return future

    def send_goal(self, goal: Any, timeout_sec: float = 30.0,
                  feedback_callback: Optional[Callable[[Any], None]] = None) -> Any:
        """
        Return the result of a goal.

        Raise TimeoutError if it does not end in time, RuntimeError if the
        server rejects it.
        """
        deadline = time.monotonic() + timeout_sec
        if not self.client.wait_for_server(timeout_sec=timeout_sec):
            raise TimeoutError(f'no action server of {self.name} within {timeout_sec} s')
        goal_handle = wait_for(
            self.client.send_goal_async(goal, feedback_callback=feedback_callback),
            deadline, f'the acceptance of a goal of {self.name}')
        if not goal_handle.accepted:
            raise RuntimeError(f'the goal was rejected by the server of {self.name}')
        response = wait_for(goal_handle.get_result_async(), deadline,
                            f'the result of a goal of {self.name}')
        return response.result

    def _accepted(self, future: Future) -> None:
        goal_handle = future.result()
        if goal_handle is None or not goal_handle.accepted:
            self._node.get_logger().warning(f'a goal of {self.name} was rejected')
            return
        # accepted while a cleanup released the port, in another thread: the
        # client is gone, and asking it for the result raised in the executor,
        # which ended the process (and every instance it held)
        _unless_destroyed(
            self.client._client_handle,
            lambda: goal_handle.get_result_async().add_done_callback(self._finished), None)

    def _finished(self, future: Future) -> None:
        if self._on_result is not None and future.exception() is None:
            response: Any = future.result()
            self._on_result(response.result)

    def destroy(self) -> None:
        """Release the client."""
        self.client.destroy()
