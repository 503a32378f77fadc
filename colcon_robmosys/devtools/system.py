# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""Bring a generated system up the way its launch files would, without launch_ros.

launch_ros is not on PyPI, so tests and the demo read the generated ``launch.py``
(as Python source, never executing it), start each node with the command line
launch_ros would build, and drive the lifecycle through the nodes' real services.
"""

from __future__ import annotations

import ast
from dataclasses import dataclass, field
import os
from pathlib import Path
import time
from typing import Any, Callable

from colcon_robmosys.devtools.ros_env import FASTDDS_PROFILE


@dataclass(frozen=True)
class NodeLaunch:
    """One ``LifecycleNode(...)`` of a generated launch file, as plain data."""

    package: str
    executable: str
    name: str
    namespace: str
    remappings: tuple[tuple[str, str], ...]
    params_files: tuple[Path, ...]
    extra: dict[str, Any] = field(default_factory=dict)

    @property
    def fqn(self) -> str:
        """Return the fully qualified node name."""
        return f"{self.namespace.rstrip('/')}/{self.name}"

    def command(self, install_dir: Path) -> list[str]:
        """Return the command line launch_ros runs for this node."""
        executable = install_dir / self.package / 'lib' / self.package / self.executable
        return [str(executable), *self.ros_args()]

    def ros_args(self) -> list[str]:
        """Return the ``--ros-args`` part of the command line, as launch_ros builds it."""
        args = ['--ros-args', '-r', f'__node:={self.name}']
        if self.namespace:
            args += ['-r', f'__ns:={self.namespace}']
        for params_file in self.params_files:
            args += ['--params-file', str(params_file)]
        for source, target in self.remappings:
            args += ['-r', f'{source}:={target}']
        return args


def _literal(node: ast.AST, names: dict[str, Any]) -> Any:
    if isinstance(node, ast.Name) and node.id in names:
        return names[node.id]
    if isinstance(node, ast.List):
        return [_literal(item, names) for item in node.elts]
    return ast.literal_eval(node)


def nodes_launch_file(share_dir: Path, instance: str = '') -> Path:
    """Return the launch file of a system package that starts its nodes (all, or one)."""
    stem = share_dir.name + (f'.{instance}' if instance else '')
    return share_dir / 'launch' / f'{stem}.nodes.launch.py'


def activate_launch_file(share_dir: Path, instance: str = '') -> Path:
    """Return the launch file of a system package that starts and activates its nodes."""
    stem = share_dir.name + (f'.{instance}' if instance else '')
    return share_dir / 'launch' / f'{stem}.launch.py'


def read_launch_file(path: Path, share_dir: Path) -> list[NodeLaunch]:
    """Return the lifecycle nodes a generated launch file starts.

    :param share_dir: ``share/<system package>`` of the install, where the
      ``params_file`` of the launch file resolves
    """
    tree = ast.parse(path.read_text(encoding='utf-8'), filename=str(path))
    names: dict[str, Any] = {}
    for node in ast.walk(tree):
        # params_file = os.path.join(get_package_share_directory(pkg), 'cfg/...')
        if isinstance(node, ast.Assign) and isinstance(node.value, ast.Call) and \
                len(node.targets) == 1 and isinstance(node.targets[0], ast.Name):
            call = node.value
            first = call.args[0] if call.args else None
            if ast.unparse(call.func) == 'os.path.join' and \
                    isinstance(first, ast.Call) and \
                    ast.unparse(first.func) == 'get_package_share_directory':
                relative = ast.literal_eval(call.args[1])
                names[node.targets[0].id] = share_dir / relative
    nodes = []
    for node in ast.walk(tree):
        # the instances: lifecycle nodes, and plain external nodes (the system
        # manager, a Node too, has no name of an instance)
        if isinstance(node, ast.Call) and \
                ast.unparse(node.func) in ('LifecycleNode', 'Node') and \
                any(k.arg == 'name' for k in node.keywords):
            kwargs = {k.arg: _literal(k.value, names) for k in node.keywords
                      if k.arg is not None}
            nodes.append(NodeLaunch(
                package=kwargs.pop('package'),
                executable=kwargs.pop('executable'),
                name=kwargs.pop('name'),
                namespace=kwargs.pop('namespace', ''),
                remappings=tuple(tuple(r) for r in kwargs.pop('remappings', [])),
                params_files=tuple(Path(p) for p in kwargs.pop('parameters', [])),
                extra=kwargs))
    return nodes


def read_activate_after(path: Path) -> dict[str, list[str]]:
    """Return the ``ACTIVATE_AFTER`` table of a generated activate file.

    Its keys are the instances the file manages (configures and activates),
    each with the instances that must be active before it is activated.
    """
    tree = ast.parse(path.read_text(encoding='utf-8'), filename=str(path))
    assignment = next(n for n in tree.body if isinstance(n, ast.Assign) and
                      ast.unparse(n.targets[0]) == 'ACTIVATE_AFTER')
    return ast.literal_eval(assignment.value)


def activation_waves(activate_after: dict[str, list[str]]) -> list[list[str]]:
    """Return the managed instances in waves: each once those it comes after are active."""
    waves: list[list[str]] = []
    done: set[str] = set()
    while len(done) < len(activate_after):
        wave = [n for n, after in activate_after.items()
                if n not in done and all(a in done for a in after)]
        if not wave:
            raise ValueError(f'activation order cycle in {activate_after}')
        waves.append(wave)
        done.update(wave)
    return waves


def wait_until(condition: Callable[[], bool], timeout: float, period: float = 0.1) -> bool:
    """Poll ``condition`` until it holds or ``timeout`` seconds pass."""
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        if condition():
            return True
        time.sleep(period)
    return condition()


#: transition label -> the state a node is in once it went through it
GOAL_STATES = {'configure': 'inactive', 'activate': 'active', 'deactivate': 'inactive',
               'cleanup': 'unconfigured', 'shutdown': 'finalized'}


class LifecycleDriver:
    """An rclpy node in this process that calls lifecycle and parameter services.

    It only uses interfaces from the ROS prefix (lifecycle_msgs, rcl_interfaces),
    so it needs nothing of the workspace under test.
    """

    def __init__(self, domain_id: int) -> None:
        # DDS reads its profile when the participant is created, so set it first
        os.environ['FASTDDS_DEFAULT_PROFILES_FILE'] = str(FASTDDS_PROFILE)
        os.environ['ROS_AUTOMATIC_DISCOVERY_RANGE'] = 'LOCALHOST'
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
              attempt: float = 5.0) -> Any:
        """Call a service whose request can be repeated, until it answers.

        A request sent before the server's answer reaches this client (DDS
        matches the two directions of a service one at a time) is answered
        into the void: it is sent again after ``attempt`` seconds.
        """
        deadline = time.monotonic() + timeout
        client = self._client(srv_type, name, timeout)
        while True:
            future = client.call_async(request)
            left = deadline - time.monotonic()
            self.executor.spin_until_future_complete(future, timeout_sec=min(attempt, left))
            if future.done():
                return future.result()
            client.remove_pending_request(future)
            if time.monotonic() >= deadline:
                raise TimeoutError(f'service {name} did not answer within {timeout} s')

    def call(self, srv_type: type, name: str, request: Any, timeout: float = 20.0,
             attempt: float = 5.0) -> Any:
        """Call a service; a request that can be repeated is sent again every ``attempt`` s."""
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
        while True:
            future = client.call_async(request)
            left = deadline - time.monotonic()
            self.executor.spin_until_future_complete(future, timeout_sec=min(5.0, left))
            if future.done():
                return bool(future.result().success)
            client.remove_pending_request(future)
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
