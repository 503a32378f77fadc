# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""
Load C++ instances into a component container, as launch_ros's LoadComposableNodes does.

With ``processes: shared`` the C++ instances of each host share one
rclcpp_components container; the manager (on its host) or the host's bringup
(``bringup --host``, on the others) asks it to load each instance's node
(``_container/load_node``) with the name, namespace, remappings and parameters
its own process would have had. composition_interfaces comes with rclcpp (it
is not on PyPI), so it is imported only when a container is used.
"""

from __future__ import annotations

import threading
import time
from typing import Any, Dict, List, Optional

from rclpy.node import Node
from rclpy.parameter import Parameter
from robmosys_runtime.processes import container_fqn, container_node
import yaml


def node_parameters(params_file: str, fqn: str) -> List[Any]:
    """Return the parameters a params file gives a node, as rcl_interfaces messages."""
    with open(params_file, encoding='utf-8') as stream:
        document = yaml.safe_load(stream) or {}
    values: Dict[str, Any] = {}
    # '/**' first: the node's own entry wins, as in rcl's parameter files
    for key in ('/**', fqn, fqn.lstrip('/')):
        entry = document.get(key) or {}
        _flatten(entry.get('ros__parameters') or {}, '', values)
    return [Parameter(name, value=value).to_parameter_msg() for name, value in values.items()]


def _flatten(tree: Dict[str, Any], prefix: str, into: Dict[str, Any]) -> None:
    for name, value in tree.items():
        if isinstance(value, dict):
            _flatten(value, f'{prefix}{name}.', into)
        else:
            into[f'{prefix}{name}'] = value


def load_into(node: Node, container: str, instances: List[Dict[str, Any]], params_file: str,
              timeout: float) -> Dict[str, str]:
    """
    Load the nodes of instances into a container; return instance -> why it failed.

    :param container: the container's fully qualified node name
    :param timeout: seconds for the container to appear, and for each load
    """
    from composition_interfaces.srv import LoadNode
    client: Any = node.create_client(LoadNode, f'{container}/_container/load_node')
    failed: Dict[str, str] = {}
    try:
        if not client.wait_for_service(timeout_sec=timeout):
            return {i['instance']: f'its container {container} did not appear within '
                    f'{timeout:g} s' for i in instances}
        for instance in instances:
            request = LoadNode.Request(
                package_name=instance['package'], plugin_name=instance['plugin'],
                node_name=instance['name'], node_namespace=instance['namespace'] or '/',
                remap_rules=[f'{s}:={t}' for s, t in instance['remappings']],
                parameters=node_parameters(params_file, instance['fqn']))
            answer = _call(client, request, timeout)
            if answer is None:
                failed[instance['instance']] = f'was not loaded within {timeout:g} s'
            elif not answer.success:
                failed[instance['instance']] = f'could not be loaded: {answer.error_message}'
    finally:
        node.destroy_client(client)
    return failed


def load_on_host(description: Dict[str, Any], host: str, names: List[str], params_file: str,
                 timeout: float) -> Dict[str, str]:
    """
    Load a host's C++ instances into its container; return instance -> why it failed.

    ``bringup --host`` does it for the instances of its host: the manager, on
    another host, brings them up once they are loaded, as any other instance.
    """
    # the smoke test's node of a context of its own, spun while the loads are answered
    from robmosys_runtime.smoke import spinning_node
    instances = {i['instance']: i for i in description['instances']}
    with spinning_node(container_node(description['package'], host) + '_loader') as node:
        return load_into(node, container_fqn(description, host),
                         [instances[n] for n in names], params_file, timeout)


def _call(client: Any, request: Any, timeout: float) -> Optional[Any]:
    answered = threading.Event()
    future = client.call_async(request)
    future.add_done_callback(lambda _: answered.set())
    deadline = time.monotonic() + timeout
    while not answered.wait(0.1):
        if time.monotonic() > deadline:
            client.remove_pending_request(future)
            return None
    return future.result()
