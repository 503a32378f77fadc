# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""A real rclpy context and a multi-threaded executor spinning in a thread, per test."""

import threading
import time

import pytest
import rclpy
from rclpy.executors import MultiThreadedExecutor
from robmosys_runtime.main import spin


class Spinning:
    """The nodes of a test, spun by a multi-threaded executor in a thread."""

    def __init__(self, context) -> None:
        self.context = context
        self.executor = MultiThreadedExecutor(num_threads=4, context=context)
        self.nodes = []
        #: what ended the spinning before the context did, raised by close()
        self.error = None
        self._thread = threading.Thread(target=self._spin, daemon=True)
        self._thread.start()

    def _spin(self) -> None:
        # as the generated processes spin: a test's transition destroys a
        # node's timers in the test's thread while the executor may gather
        # them (ros2/rclpy#1142), which a plain spin() did not survive: the
        # thread ended and no timer fired again
        try:
            spin(self.executor)
        except Exception as error:  # noqa: B902 - raised by close() unless the context ended
            if self.context.ok():
                self.error = error

    def add(self, node):
        """Spin a node; return it."""
        self.nodes.append(node)
        self.executor.add_node(node)
        return node

    def close(self) -> None:
        self.executor.shutdown()
        for node in self.nodes:
            node.destroy_node()
        rclpy.try_shutdown(context=self.context)
        self._thread.join(10)
        if self.error is not None:
            raise self.error


def wait_until(condition, timeout: float = 10.0) -> bool:
    """Wait until condition() holds, at most timeout seconds; return whether it did."""
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        if condition():
            return True
        time.sleep(0.02)
    return bool(condition())


def answer(client, request, timeout: float = 20.0, executor=None):
    """
    Return the answer of a client to a request that may be asked again.

    rmw_fastrtps drops an answer to a client whose reader of answers the server
    has not matched within 100 ms ('failed to send response'): the request is
    asked again, soon and then less often, until one comes within timeout.

    :param executor: the client's executor, spun here; None: another thread spins it
    :returns: the answer, None if none came within timeout
    """
    deadline = time.monotonic() + timeout
    attempt = 1.0
    while True:
        done = threading.Event()
        future = client.call_async(request)
        future.add_done_callback(lambda _: done.set())
        wait = max(0.0, min(attempt, deadline - time.monotonic()))
        if executor is not None:
            executor.spin_until_future_complete(future, timeout_sec=wait)
        if done.wait(0.0 if executor is not None else wait):
            return future.result()
        client.remove_pending_request(future)
        if time.monotonic() >= deadline:
            return None
        attempt *= 2


@pytest.fixture
def spinning():
    context = rclpy.Context()
    rclpy.init(context=context)
    running = Spinning(context)
    yield running
    running.close()
