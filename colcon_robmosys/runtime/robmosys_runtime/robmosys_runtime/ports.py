# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""The client ports of the query and action patterns: blocking and asynchronous calls."""

from __future__ import annotations

import threading
import time
from typing import Any, Callable, Optional

from rclpy.action import ActionClient
from rclpy.callback_groups import MutuallyExclusiveCallbackGroup
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
        goal_handle.get_result_async().add_done_callback(self._finished)

    def _finished(self, future: Future) -> None:
        if self._on_result is not None and future.exception() is None:
            response: Any = future.result()
            self._on_result(response.result)

    def destroy(self) -> None:
        """Release the client."""
        self.client.destroy()
