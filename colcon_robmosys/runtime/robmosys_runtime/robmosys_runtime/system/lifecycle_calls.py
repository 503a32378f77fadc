# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""
The lifecycle services of a system's instances, called from many threads.

Each instance is asked its state (``get_state``) and taken through its
transitions (``change_state``) by one client per service, made once. An
answer lost on its way (DDS matches the two directions of a service one at
a time) is asked again, or, for a transition, which cannot be asked twice,
read from the state the instance tells.
"""

from __future__ import annotations

import threading
import time
from typing import Any, Callable, Dict, Mapping, Optional, Tuple

from lifecycle_msgs.msg import Transition
from lifecycle_msgs.srv import ChangeState, GetState
from rclpy.node import Node

#: transition -> the state a node is in once it went through it
GOAL_STATES = {Transition.TRANSITION_CONFIGURE: 'inactive',
               Transition.TRANSITION_ACTIVATE: 'active',
               Transition.TRANSITION_DEACTIVATE: 'inactive',
               Transition.TRANSITION_CLEANUP: 'unconfigured'}

#: seconds to wait for the first answer of get_state before asking again;
#: each next wait doubles, up to LAST_ATTEMPT
FIRST_ATTEMPT = 0.25
LAST_ATTEMPT = 2.0

#: what the report says of a transition that failed
VERBS = {Transition.TRANSITION_CONFIGURE: 'configure',
         Transition.TRANSITION_ACTIVATE: 'activate',
         Transition.TRANSITION_DEACTIVATE: 'deactivate',
         Transition.TRANSITION_CLEANUP: 'clean up'}


class Stopped(Exception):
    """The bring-up was stopped (the launch or the process ends)."""


class Failed(Exception):
    """An instance that cannot be brought up, and why."""


class LifecycleCalls:
    """
    The lifecycle services of the instances of a system.

    :param instances: instance name -> fully qualified node name
    :param timeout: seconds for each transition
    :param start_timeout: seconds for each instance to offer its services
    :param timeouts: instance name -> seconds for each of its transitions
    :param stop: set when every call is to end (:class:`Stopped`)
    :param failed: tells whether an instance failed from outside (its
        process died): its calls end too
    """

    def __init__(self, node: Node, instances: Mapping[str, str], *, timeout: float,
                 start_timeout: float, timeouts: Mapping[str, float],
                 stop: threading.Event, failed: Callable[[str], bool]) -> None:
        self._node = node
        self._instances = dict(instances)
        self._timeout = timeout
        self._start_timeout = start_timeout
        self._timeouts = dict(timeouts)
        self._stop = stop
        self._failed = failed
        self._lock = threading.Lock()
        self._clients: Dict[Tuple[str, str], Any] = {}
        #: instance -> when its get_state client was made, until its service is seen
        self._unseen: Dict[str, float] = {}

    def call(self, client: Any, request: Any, wait: float, failed_too: bool = False) -> Any:
        """Call a service; return its answer, or None if none came within wait seconds."""
        answered = threading.Event()
        future = client.call_async(request)
        future.add_done_callback(lambda _: answered.set())
        if self.wait_answer(answered, client, future, wait, failed_too):
            return future.result()
        client.remove_pending_request(future)
        return None

    def wait_answer(self, answered: threading.Event, client: Any, future: Any,
                    wait: float, failed_too: bool = False) -> bool:
        """
        Wait at most wait seconds for the answer of a call; return whether it came.

        :param failed_too: wait even if the instance failed (else: :class:`Stopped`)
        """
        end = time.monotonic() + wait
        while not answered.wait(max(0.0, min(0.1, end - time.monotonic()))):
            if self._stop.is_set() or not self._node.context.ok() or \
                    (not failed_too and self._gone(client)):
                client.remove_pending_request(future)
                raise Stopped()
            if time.monotonic() >= end:
                return False
        return True

    def _gone(self, client: Any) -> bool:
        """Tell whether the instance of a client failed from outside (its process died)."""
        return any(client.srv_name.startswith(f'{fqn}/')
                   for name, fqn in self._instances.items() if self._failed(name))

    def _client(self, name: str, srv_type: Any, service: str) -> Any:
        """Return the client of a service of an instance, made once."""
        with self._lock:
            client: Any = self._clients.get((name, service))
            if client is None:
                client = self._node.create_client(
                    srv_type, f'{self._instances[name]}/{service}')
                self._clients[(name, service)] = client
                if service == 'get_state':
                    self._unseen[name] = time.monotonic()
        return client

    def prepare(self, name: str) -> None:
        """
        Make the clients of an instance's lifecycle services, without waiting for them.

        For an instance whose state its process told: its services are then
        discovered in the background, for the heartbeat and the bring-down.
        """
        self._client(name, GetState, 'get_state')
        self._client(name, ChangeState, 'change_state')

    def discovering(self, name: str) -> bool:
        """
        Tell whether an instance's get_state is still to be seen, within its start timeout.

        Its process told its state, and the service was not needed so far: a
        heartbeat that finds it not discovered yet has no answer to miss.
        """
        with self._lock:
            made = self._unseen.get(name)
            return (name, 'get_state') not in self._clients or (
                made is not None and time.monotonic() - made < self._start_timeout)

    def client(self, name: str, srv_type: Any, service: str,
               timeout: Optional[float] = None, failed_too: bool = False) -> Any:
        """Return the client of a service of an instance, once the instance offers it."""
        client = self._client(name, srv_type, service)
        timeout = self._start_timeout if timeout is None else timeout
        deadline = time.monotonic() + timeout
        # not wait_for_service(): it sleeps in steps of 0.25 s, which every
        # instance would pay on its way up
        while not client.service_is_ready():
            if self._stop.wait(0.02) or not self._node.context.ok() or \
                    (not failed_too and self._failed(name)):
                raise Stopped()
            if time.monotonic() > deadline:
                absence = self._absence(name, service)
                raise Failed(f'did not appear within {timeout:g} s ({absence})')
        if service == 'get_state':
            with self._lock:
                self._unseen.pop(name, None)
        return client

    def _absence(self, name: str, service: str) -> str:
        """
        Tell what the ROS graph has of an instance whose service was not seen.

        A node missing from the graph was not made, or its participant was not
        discovered; a node there without the service is no lifecycle node; a
        service there that this client did not match lost its DDS matching.
        """
        fqn = self._instances[name]
        namespace, _, node_name = fqn.rpartition('/')
        namespace = namespace or '/'
        if (node_name, namespace) not in self._node.get_node_names_and_namespaces():
            return f'no node {fqn} in the ROS graph'
        services = self._node.get_service_names_and_types_by_node(node_name, namespace)
        if f'{fqn}/{service}' not in {s for s, _ in services}:
            return f'its node is in the ROS graph, without a {service} service'
        return f'its {service} service is in the ROS graph, but did not match this client'

    def timeout_of(self, name: str) -> float:
        """Return the seconds each transition of an instance may take."""
        return self._timeouts.get(name, self._timeout)

    def get_state(self, name: str, timeout: Optional[float] = None,
                  failed_too: bool = False) -> Optional[str]:
        """
        Return the state of an instance; None if it does not answer within timeout.

        :param failed_too: ask even an instance that failed (see :meth:`wait_answer`)
        """
        client = self.client(name, GetState, 'get_state', timeout, failed_too)
        own = self.timeout_of(name)
        deadline = time.monotonic() + (own if timeout is None else timeout)
        # An answer is lost when the instance got the request before it matched
        # this client's reader of answers (DDS matches the two directions of a
        # service one at a time; rmw_fastrtps then waits 100 ms and drops it):
        # asking again soon, then less often, costs a lost answer a quarter of
        # a second, not seconds, while a busy instance is not flooded.
        attempt = FIRST_ATTEMPT
        while True:
            answer = self.call(client, GetState.Request(),
                               min(attempt, max(0.0, deadline - time.monotonic())), failed_too)
            if answer is not None:
                return str(answer.current_state.label)
            if time.monotonic() >= deadline:
                if timeout is not None:
                    return None
                raise Failed(f'did not tell its state within {own:g} s')
            attempt = min(2 * attempt, LAST_ATTEMPT)

    def change(self, name: str, transition: int, timeout: Optional[float] = None) -> str:
        """Take an instance through a transition; return the state it is then in."""
        timeout = self.timeout_of(name) if timeout is None else timeout
        client = self.client(name, ChangeState, 'change_state', timeout)
        request = ChangeState.Request()
        request.transition = Transition(id=transition)
        deadline = time.monotonic() + timeout
        goal = GOAL_STATES[transition]
        answered = threading.Event()
        future = client.call_async(request)
        future.add_done_callback(lambda _: answered.set())
        # A transition cannot be asked for twice; its answer may be lost where
        # the transition was not (see get_state): while none comes, the state
        # the instance tells says whether it got there.
        state: Optional[str] = None
        attempt = 2 * FIRST_ATTEMPT
        while not self.wait_answer(answered, client, future,
                                   min(attempt, deadline - time.monotonic())):
            attempt = min(2 * attempt, LAST_ATTEMPT)
            state = self.get_state(name, timeout=max(
                0.1, min(LAST_ATTEMPT, deadline - time.monotonic())))
            if state == goal:
                client.remove_pending_request(future)
                return goal
            if time.monotonic() >= deadline:
                client.remove_pending_request(future)
                now = f'it is {state}' if state else 'it does not answer'
                raise Failed(f'did not {VERBS[transition]} within {timeout:g} s ({now})')
        answer = future.result()
        if not answer.success:
            state = self.get_state(name) or 'unknown'
            raise Failed(f'failed to {VERBS[transition]} (it is {state})')
        # a transition that succeeded ends in its goal state: no need to ask
        return GOAL_STATES[transition]
