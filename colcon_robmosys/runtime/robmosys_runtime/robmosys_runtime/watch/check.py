# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""
``bringup --check``: a running system compared with its model once.

However the system was started, :func:`check_once` waits for the nodes of the
model, asks each managed instance its state and each instance the parameters
the model sets, listens to the watched push ports a while, and compares once.
"""

from __future__ import annotations

import os
import threading
import time
from typing import Any, Dict, List

from rclpy.node import Node
from robmosys_runtime.watch.conformance import Difference, Model
from robmosys_runtime.watch.watcher import read_parameters, Watch


def check_once(description: Dict[str, Any], *, wait: float = 10.0, silence: float = 5.0,
               period: float = 1.0) -> List[Difference]:
    """
    Compare a running system with its model once; return the differences.

    It waits up to ``wait`` seconds for every node of the model to appear,
    asks each lifecycle instance its state and each instance the parameters
    the model sets, and listens to the push ports of periodic activities
    for ``silence`` of their periods (at most ``wait`` more seconds). A
    difference is one that lasts: while there are some, it compares again for
    up to ``wait`` more seconds, as another process's endpoints reach this one.
    """
    import rclpy
    from rclpy.executors import MultiThreadedExecutor
    context = rclpy.Context()
    rclpy.init(context=context, args=['--ros-args', '--disable-rosout-logs'])
    node = rclpy.create_node(f"{description['package']}_check_{os.getpid()}",
                             context=context, start_parameter_services=False)
    executor = MultiThreadedExecutor(num_threads=2, context=context)
    executor.add_node(node)
    spinner = threading.Thread(target=executor.spin, daemon=True)
    spinner.start()
    try:
        watch = Watch(node, description, period=period, silence=silence,
                      report=lambda d, a: None, grace=0.0, confirm=1)
        model = watch.model
        fqns = {i['fqn'] for i in model.instances.values()}
        deadline = time.monotonic() + wait
        while time.monotonic() < deadline and \
                not fqns <= set(node.get_fully_qualified_node_names()):
            time.sleep(0.1)
        start = time.monotonic()
        present = set(node.get_fully_qualified_node_names())
        states = _states(node, model, present, wait)
        read_parameters(node, [i for i in model.instances.values() if i['fqn'] in present],
                        watch._listener, wait)
        periods = [p['period'] for i in model.instances.values() for p in i.get('ports', ())
                   if p.get('period') and not p.get('quiet')]
        listen = min(wait, max([silence * p for p in periods] + [0.0]))
        # listened since the node was made: the window counts from discovery
        time.sleep(max(0.0, start + listen - time.monotonic()) + 0.2)
        watch._up_since = {n: start for n in model.instances}
        watch._settled_since = start
        watch.period = 0.0
        found = watch.check(states, settled=True)
        # a difference may be discovery still under way here (an endpoint of another
        # process not yet announced to this new one): only one that lasts counts;
        # and a graph that does not name every end yet is compared again
        settle = time.monotonic() + wait
        while (found or not watch.compared) and time.monotonic() < settle:
            time.sleep(0.5)
            found = watch.check(states, settled=True)
        return list(found.values())
    finally:
        executor.shutdown()
        spinner.join(10)
        node.destroy_node()
        rclpy.try_shutdown(context=context)


def _states(node: Node, model: Model, present: Any, timeout: float) -> Dict[str, str]:
    """Ask each managed instance its lifecycle state."""
    from lifecycle_msgs.srv import GetState
    states: Dict[str, str] = {}
    pending = []
    for name, instance in model.instances.items():
        if not instance['managed']:
            states[name] = 'running'
            continue
        if instance['fqn'] not in present:
            states[name] = 'absent'
            continue
        client: Any = node.create_client(GetState, f"{instance['fqn']}/get_state")
        pending.append((name, client, client.call_async(GetState.Request())
                        if client.wait_for_service(timeout_sec=timeout) else None))
    deadline = time.monotonic() + timeout
    for name, client, future in pending:
        while future is not None and not future.done() and time.monotonic() < deadline:
            time.sleep(0.02)
        answer = future.result() if future is not None and future.done() else None
        if answer is not None:
            states[name] = answer.current_state.label
        else:
            states[name] = 'unknown (no answer)'
        node.destroy_client(client)
    return states
