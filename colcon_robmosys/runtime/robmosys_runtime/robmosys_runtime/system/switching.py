# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""
The service calls of a mode switch, made by the switching thread on a node of its own.

A switch is a row of calls, each waited for before the next. Through the
manager's node each answer went from its multi-threaded executor to the
waiting thread (a task of its pool, then an event): a switch took 1.4 times
as long as the same calls made by a plain rclpy node spinning its own
executor (bench/bench_modes.py). Here the thread that switches spins the
executor of a hidden node (``/_<manager>_modes``) until its answer is there,
as such a node does.
"""

from __future__ import annotations

import time
from typing import Any, Callable, Dict, Optional, Tuple

from lifecycle_msgs.msg import Transition
from lifecycle_msgs.srv import ChangeState
from rclpy.node import Node
from robmosys_runtime.system.lifecycle_calls import (
    Failed, FIRST_ATTEMPT, GOAL_STATES, LAST_ATTEMPT, VERBS)


class SwitchCalls:
    """
    The lifecycle and parameter services of the instances, called by one thread at a time.

    :param node: the manager's node: this one is made in its context and namespace
    :param instances: instance name -> fully qualified node name
    """

    def __init__(self, node: Node, instances: Dict[str, str]) -> None:
        import rclpy
        from rclpy.executors import SingleThreadedExecutor
        self.node = rclpy.create_node(
            f'_{node.get_name()}_modes', namespace=node.get_namespace(), context=node.context,
            # a remap of __node among the global arguments (bringup's) renames every node
            use_global_arguments=False, start_parameter_services=False, enable_rosout=False)
        self.executor = SingleThreadedExecutor(context=node.context)
        self.executor.add_node(self.node)
        self._instances = instances
        self._clients: Dict[Tuple[str, str], Any] = {}

    def client(self, name: str, srv_type: Any, service: str, timeout: float) -> Any:
        """Return the client of a service of an instance once it is ready; raise if it is not."""
        key = (name, service)
        client = self._clients.get(key)
        if client is None:
            client = self._clients[key] = self.node.create_client(
                srv_type, f'{self._instances[name]}/{service}')
        deadline = time.monotonic() + timeout
        while not client.service_is_ready():
            if time.monotonic() > deadline:
                raise Failed(f'did not offer {service} within {timeout:g} s')
            self.executor.spin_once(timeout_sec=0.02)
        return client

    def wait(self, futures: Dict[str, Any], timeout: float) -> None:
        """Spin until every future is done, or timeout seconds passed."""
        deadline = time.monotonic() + timeout
        for future in futures.values():
            left = deadline - time.monotonic()
            if left <= 0:
                return
            if not future.done():
                self.executor.spin_until_future_complete(future, timeout_sec=left)

    def change(self, name: str, transition: int, timeout: float,
               state_of: Callable[[], Optional[str]]) -> str:
        """
        Take an instance through a transition; return the state it is then in.

        An answer lost (see :mod:`.lifecycle_calls`) is made up for by the state the
        instance tells (``state_of``): the transition cannot be asked for twice.
        """
        client = self.client(name, ChangeState, 'change_state', timeout)
        request = ChangeState.Request()
        request.transition = Transition(id=transition)
        future = client.call_async(request)
        deadline = time.monotonic() + timeout
        attempt = 2 * FIRST_ATTEMPT
        while True:
            self.wait({name: future}, min(attempt, max(0.0, deadline - time.monotonic())))
            if future.done():
                break
            state = state_of()
            if state == GOAL_STATES[transition] or time.monotonic() >= deadline:
                client.remove_pending_request(future)
                if state == GOAL_STATES[transition]:
                    return state
                now = f'it is {state}' if state else 'it does not answer'
                raise Failed(f'did not {VERBS[transition]} within {timeout:g} s ({now})')
            attempt = min(2 * attempt, LAST_ATTEMPT)
        if not future.result().success:
            state = state_of() or 'unknown'
            raise Failed(f'failed to {VERBS[transition]} (it is {state})')
        return GOAL_STATES[transition]

    def set_values(self, requests: Dict[str, Any], timeout: float) -> Dict[str, Any]:
        """
        Call set_parameters of several instances at once; return each answer (None: none came).

        A request not answered is sent again (an answer lost while the service's two
        directions match; setting the same values twice changes nothing).
        """
        from rcl_interfaces.srv import SetParameters
        deadline = time.monotonic() + timeout
        answers: Dict[str, Any] = {}
        attempt = FIRST_ATTEMPT
        while len(answers) < len(requests) and time.monotonic() < deadline:
            futures = {
                name: (self.client(name, SetParameters, 'set_parameters',
                                   max(0.0, deadline - time.monotonic())), request)
                for name, request in requests.items() if name not in answers}
            sent = {name: client.call_async(request) for name, (client, request)
                    in futures.items()}
            self.wait(sent, min(attempt, max(0.0, deadline - time.monotonic())))
            for name, future in sent.items():
                if future.done():
                    answers[name] = future.result()
                else:
                    futures[name][0].remove_pending_request(future)
            attempt = min(2 * attempt, LAST_ATTEMPT)
        return {name: answers.get(name) for name in requests}

    def close(self) -> None:
        """Destroy the node (before the context ends)."""
        self.executor.shutdown()
        self.node.destroy_node()
