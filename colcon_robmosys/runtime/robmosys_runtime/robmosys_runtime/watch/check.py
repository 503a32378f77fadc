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
from typing import Any, Dict, List, Optional, Tuple

from rclpy.node import Node
from robmosys_runtime.watch.conformance import Difference, Model, same_value
from robmosys_runtime.watch.watcher import read_parameters, Watch

#: seconds after which a state asked and not answered is asked again
ASK_AGAIN = 2.0


def check_once(description: Dict[str, Any], *, wait: float = 10.0, silence: float = 5.0,
               period: float = 1.0, mode: str = '',
               notes: Optional[List[str]] = None) -> List[Difference]:
    """
    Compare a running system with its model once; return the differences.

    It waits up to ``wait`` seconds for every node of the model to appear,
    asks each lifecycle instance its state and each instance the parameters
    the model sets, and listens to the push ports of periodic activities
    for ``silence`` of their periods (at most ``wait`` more seconds). A
    difference is one that lasts: while there are some, it compares again for
    up to ``wait`` more seconds, as another process's endpoints reach this one.

    A system with modes is compared with ``mode``, or with the mode its
    instances and values show (:func:`inferred_mode`); ``notes`` gets a line
    that names it.
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
        modes = {m['name']: m for m in description.get('modes', ())}
        if modes:
            how = 'given'
            if not mode:
                mode, how = inferred_mode(description, states, watch._listener.values())
            if notes is not None:
                notes.append(f'mode: {mode} ({how})')
            watch.expect(mode, {n for n, i in model.instances.items() if i['managed']} -
                         set(modes[mode]['active']), modes[mode]['values'],
                         modes[mode].get('location', ''))
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


def inferred_mode(description: Dict[str, Any], states: Dict[str, str],
                  values: Dict[str, Dict[str, Any]]) -> Tuple[str, str]:
    """
    Return the mode a running system is in, as its states and values show, and how it shows.

    The mode whose active instances are those active, and whose values the nodes
    hold; else the nearest (the fewest instances in another state, then the fewest
    values), the first of the model's on a tie.

    :param values: node fqn -> parameter -> value read
    """
    fqn = {i['instance']: i['fqn'] for i in description['instances']}
    active = {n for n, s in states.items() if s == 'active' and
              any(i['instance'] == n and i['managed'] for i in description['instances'])}
    scored = []
    for mode in description['modes']:
        states_off = len(active ^ set(mode['active']))
        values_off = sum(1 for name, given in mode['values'].items()
                         for parameter, value in given.items()
                         if parameter in values.get(fqn[name], {}) and
                         not same_value(values[fqn[name]][parameter], value))
        scored.append((states_off, values_off, mode['name']))
    best = min(scored, key=lambda s: s[:2])
    if best[:2] == (0, 0):
        return best[2], 'inferred: its active instances and values are those of the mode'
    return best[2], (f'inferred: the nearest mode; {best[0]} instance(s) in another state, '
                     f'{best[1]} value(s) other than its')


def _states(node: Node, model: Model, present: Any, timeout: float) -> Dict[str, str]:
    """
    Ask each managed instance its lifecycle state, all at once, within timeout.

    rmw_fastrtps drops an answer to a client whose reader of answers the server
    has not matched yet, and through a discovery server this new participant's
    endpoints reach the other hosts a while after it sees theirs: a request not
    answered within ASK_AGAIN seconds is sent again.
    """
    from lifecycle_msgs.srv import GetState
    states: Dict[str, str] = {}
    clients: Dict[str, Any] = {}
    for name, instance in model.instances.items():
        if not instance['managed']:
            states[name] = 'running'
        elif instance['fqn'] not in present:
            states[name] = 'absent'
        else:
            clients[name] = node.create_client(GetState, f"{instance['fqn']}/get_state")
    asked: Dict[str, Tuple[Any, float]] = {}
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline and any(n not in states for n in clients):
        for name, client in clients.items():
            future, when = asked.get(name, (None, 0.0))
            if name in states:
                continue
            if future is not None and future.done() and future.result() is not None:
                states[name] = future.result().current_state.label
            elif time.monotonic() - when >= ASK_AGAIN and client.service_is_ready():
                if future is not None:
                    client.remove_pending_request(future)
                asked[name] = (client.call_async(GetState.Request()), time.monotonic())
        time.sleep(0.02)
    for name, client in clients.items():
        states.setdefault(name, 'unknown (no answer)')
        node.destroy_client(client)
    return states
