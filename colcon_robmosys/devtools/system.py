# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""Drive the nodes of a running system from outside, as an operator's tools would.

:class:`LifecycleDriver` calls the nodes' real lifecycle and parameter services;
tests and bench/ use it to bring nodes up and read them back.
"""

from __future__ import annotations

import os
import time
from typing import Any, Callable

from colcon_robmosys.devtools.ros_env import DISCOVERY_RANGE, FASTDDS_PROFILE


def wait_until(condition: Callable[[], bool], timeout: float, period: float = 0.1) -> bool:
    """Poll ``condition`` until it holds or ``timeout`` seconds pass."""
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        if condition():
            return True
        time.sleep(period)
    return condition()


def answered(client: Any, request: Any, spun: Any, timeout: float = 20.0,
             attempt: float = 1.0) -> Any:
    """Return the answer of a service to a request that can be asked again.

    rmw_fastrtps drops the answer to a client whose reader of answers the
    server has not matched within 100 ms (ros2/rmw_fastrtps#467, "failed to
    send response"): a request that gets no answer within ``attempt`` seconds
    is asked again, each time waiting twice as long, until ``timeout``. Only
    for requests that do the same when asked twice (reading, setting a value).

    :param spun: what completes the client's futures: its node, spun here, or
      an executor it was added to (anything with ``spin_until_future_complete``)
    :raises TimeoutError: if no answer came within ``timeout`` seconds
    """
    import rclpy
    if hasattr(spun, 'spin_until_future_complete'):
        spin = spun.spin_until_future_complete
    else:
        def spin(future: Any, timeout_sec: float) -> None:
            rclpy.spin_until_future_complete(spun, future, timeout_sec=timeout_sec)
    deadline = time.monotonic() + timeout
    while True:
        future = client.call_async(request)
        spin(future, timeout_sec=max(0.0, min(attempt, deadline - time.monotonic())))
        if future.done():
            return future.result()
        client.remove_pending_request(future)
        if time.monotonic() >= deadline:
            raise TimeoutError(f'{client.srv_name} did not answer within {timeout:g} s')
        attempt *= 2


#: transition label -> the state a node is in once it went through it
GOAL_STATES = {'configure': 'inactive', 'activate': 'active', 'deactivate': 'inactive',
               'cleanup': 'unconfigured', 'shutdown': 'finalized',
               'unconfigured_shutdown': 'finalized', 'inactive_shutdown': 'finalized',
               'active_shutdown': 'finalized'}


class LifecycleDriver:
    """An rclpy node in this process that calls lifecycle and parameter services.

    It only uses interfaces from the ROS prefix (lifecycle_msgs, rcl_interfaces),
    so it needs nothing of the workspace under test.
    """

    def __init__(self, domain_id: int) -> None:
        # DDS reads its profile when the participant is created, so set it first
        os.environ['FASTDDS_DEFAULT_PROFILES_FILE'] = str(FASTDDS_PROFILE)
        os.environ['ROS_AUTOMATIC_DISCOVERY_RANGE'] = DISCOVERY_RANGE
        os.environ['RMW_IMPLEMENTATION'] = 'rmw_fastrtps_cpp'
        import rclpy
        from rclpy.context import Context
        from rclpy.executors import SingleThreadedExecutor
        self._rclpy = rclpy
        self.context = Context()
        rclpy.init(context=self.context, domain_id=domain_id)
        self.node = rclpy.create_node('robmosys_test_driver', context=self.context)
        self.executor = SingleThreadedExecutor(context=self.context)
        self.executor.add_node(self.node)
        self._clients: dict[tuple[type, str], Any] = {}

    def close(self) -> None:
        """Destroy the node and shut the context down."""
        self.executor.shutdown()
        self.node.destroy_node()
        self._rclpy.try_shutdown(context=self.context)

    def __enter__(self) -> 'LifecycleDriver':
        return self

    def __exit__(self, *exc_info: object) -> None:
        self.close()

    def _client(self, srv_type: type, name: str, timeout: float) -> Any:
        key = (srv_type, name)
        if key not in self._clients:
            self._clients[key] = self.node.create_client(srv_type, name)
        client = self._clients[key]
        if not client.wait_for_service(timeout_sec=timeout):
            raise TimeoutError(f'service {name} did not appear within {timeout} s')
        return client

    def _call(self, srv_type: type, name: str, request: Any, timeout: float,
              attempt: float = 1.0) -> Any:
        """Call a service whose request can be repeated, until it answers (:func:`answered`)."""
        deadline = time.monotonic() + timeout
        client = self._client(srv_type, name, timeout)
        return answered(client, request, self.executor,
                        max(deadline - time.monotonic(), 0.0), attempt)

    def call(self, srv_type: type, name: str, request: Any, timeout: float = 20.0,
             attempt: float = 1.0) -> Any:
        """Call a service; a request that can be repeated is asked again (see :func:`answered`).

        :param attempt: how long the first request is waited for
        """
        return self._call(srv_type, name, request, timeout, attempt)

    def state(self, fqn: str, timeout: float = 20.0) -> str:
        """Return the label of the node's current lifecycle state."""
        from lifecycle_msgs.srv import GetState
        return self._call(GetState, f'{fqn}/get_state', GetState.Request(),
                          timeout).current_state.label

    def transition(self, fqn: str, label: str, timeout: float = 20.0) -> bool:
        """Ask a node to change its lifecycle state; return whether it did.

        An answer that does not come is asked again of ``get_state``: a
        transition cannot be requested twice, but its goal state can be read.

        :param label: the transition, e.g. ``configure``
        """
        from lifecycle_msgs.msg import Transition
        from lifecycle_msgs.srv import ChangeState
        deadline = time.monotonic() + timeout
        name = f'{fqn}/change_state'
        client = self._client(ChangeState, name, timeout)
        request = ChangeState.Request()
        request.transition = Transition(
            id=getattr(Transition, f'TRANSITION_{label.upper()}'))
        start = self.state(fqn, timeout)
        repeated = False
        while True:
            future = client.call_async(request)
            left = deadline - time.monotonic()
            self.executor.spin_until_future_complete(future, timeout_sec=min(5.0, left))
            if future.done():
                if future.result().success or not repeated:
                    return bool(future.result().success)
                # The request before this one may have come late rather than
                # never: it took the node to the goal state, and this one
                # then failed, being asked of that state.
                return self.state(fqn, max(deadline - time.monotonic(), 1.0)) == \
                    GOAL_STATES[label]
            client.remove_pending_request(future)
            repeated = True
            now = self.state(fqn, max(deadline - time.monotonic(), 1.0))
            if now == GOAL_STATES[label]:
                return True
            if now != start or time.monotonic() >= deadline:
                raise TimeoutError(f'service {name} did not answer within {timeout} s '
                                   f'(state: {now})')

    def request_transition(self, fqn: str, label: str, timeout: float = 20.0) -> Any:
        """Ask a node to change its lifecycle state, without waiting for the answer.

        :returns: the future of the ``change_state`` call; :meth:`spin` completes it
        """
        from lifecycle_msgs.msg import Transition
        from lifecycle_msgs.srv import ChangeState
        client = self._client(ChangeState, f'{fqn}/change_state', timeout)
        request = ChangeState.Request()
        request.transition = Transition(
            id=getattr(Transition, f'TRANSITION_{label.upper()}'))
        future = client.call_async(request)
        self.executor.spin_once(timeout_sec=0.01)
        return future

    def watch_transitions(self, fqns: list[str]) -> list[tuple[str, str]]:
        """Return a list that collects, in order, every state the nodes reach from now on.

        Each item is (fully qualified node name, state label), from the nodes'
        ``transition_event`` topics; :meth:`spin` delivers them.
        """
        from lifecycle_msgs.msg import TransitionEvent
        reached: list[tuple[str, str]] = []
        for fqn in fqns:
            self.node.create_subscription(
                TransitionEvent, f'{fqn}/transition_event',
                lambda msg, fqn=fqn: reached.append((fqn, msg.goal_state.label)), 100)
        return reached

    def spin(self, seconds: float = 0.1) -> None:
        """Handle what arrived for the driver's node, waiting at most ``seconds``."""
        self.executor.spin_once(timeout_sec=seconds)

    def parameters(self, fqn: str, names: list[str], timeout: float = 20.0) -> dict[str, Any]:
        """Return the current values of some parameters of a node."""
        from rcl_interfaces.srv import GetParameters
        from rclpy.parameter import parameter_value_to_python
        request = GetParameters.Request(names=names)
        answer = self._call(GetParameters, f'{fqn}/get_parameters', request, timeout)
        return {n: parameter_value_to_python(v) for n, v in zip(names, answer.values)}

    def set_parameters(self, fqn: str, values: dict[str, Any],
                       timeout: float = 20.0) -> dict[str, tuple[bool, str]]:
        """Set parameters one by one; return (successful, reason) per name."""
        from rcl_interfaces.srv import SetParameters
        from rclpy.parameter import Parameter
        request = SetParameters.Request(parameters=[
            Parameter(name, value=value).to_parameter_msg() for name, value in values.items()])
        answer = self._call(SetParameters, f'{fqn}/set_parameters', request, timeout)
        return {name: (result.successful, result.reason)
                for name, result in zip(values, answer.results)}

    def endpoints(self, fqn: str) -> dict[str, set[str]]:
        """Return the topics and services a node has, as the ROS graph sees them now."""
        namespace, _, name = fqn.rpartition('/')
        namespace = namespace or '/'
        graph = self.node
        found = {'publishers': graph.get_publisher_names_and_types_by_node,
                 'subscriptions': graph.get_subscriber_names_and_types_by_node,
                 'services': graph.get_service_names_and_types_by_node,
                 'clients': graph.get_client_names_and_types_by_node}
        result = {}
        for kind, query in found.items():
            try:
                result[kind] = {topic for topic, _ in query(name, namespace)}
            except Exception:  # noqa: B902 - rclpy raises NodeNameNonExistentError
                result[kind] = set()
        return result
