# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""Query and action connections: ROS 2 remaps a service or an action by its name.

A system's launch files connect ports by remapping only. For topics that is what
the example systems run; here a system of query and action ports is planned, and
rclpy nodes with exactly the planned names, namespaces and remappings serve and
call a service and an action (test_msgs types, from the ros-* wheels). Kilted
remaps an action by its name; Jazzy only by the names of its services and topics,
which the plan remaps too: `make test ROS_DISTRO=jazzy` runs this on Jazzy.
"""

from __future__ import annotations

from pathlib import Path
import sys
import textwrap

import pytest

from colcon_robmosys.check import load_workspace
from colcon_robmosys.check.index import InterfaceIndex
from colcon_robmosys.devtools.ros_env import background, loopback_env, run
from colcon_robmosys.devtools.system import wait_until
from colcon_robmosys.generators import plan_package
from conftest import requires_ros
from harness.launch_files import NodeLaunch

pytestmark = [pytest.mark.integration, requires_ros]

MODEL = """\
robmosys: 1
defaults:
  license: Apache-2.0
  maintainers: [{name: A, email: a@example.com}]
components:
  - name: Server
    package: remap_server
    language: python
    ports:
      qAdd: {pattern: query, role: provided, type: test_msgs/srv/BasicTypes}
      aCount: {pattern: action, role: provided, type: test_msgs/action/Fibonacci}
    activities:
      Add: {trigger: qAdd, functions: [fAdd]}
      Count: {trigger: aCount, functions: [fCount]}
    functions:
      fAdd:
      fCount:
  - name: Client
    package: remap_client
    language: python
    ports:
      qSum: {pattern: query, role: required, type: test_msgs/srv/BasicTypes}
      aFibonacci: {pattern: action, role: required, type: test_msgs/action/Fibonacci}
systems:
  - package: remap_system
    instances:
      server: {component: remap_server, namespace: robot}
      client: {component: remap_client, namespace: /ops}
    connections:
      - {from: server.qAdd, to: client.qSum}
      - {from: client.aFibonacci, to: server.aCount, topic: count}
"""

SERVER = textwrap.dedent("""
    import sys
    import rclpy
    from rclpy.action import ActionServer
    from rclpy.node import Node
    from test_msgs.action import Fibonacci
    from test_msgs.srv import BasicTypes

    rclpy.init(args=sys.argv)
    node = Node('unnamed')

    def add(request, response):
        response.int32_value = request.int32_value + 1
        return response

    def count(goal_handle):
        goal_handle.succeed()
        return Fibonacci.Result(sequence=list(range(goal_handle.request.order)))

    node.create_service(BasicTypes, 'qAdd', add)
    ActionServer(node, Fibonacci, 'aCount', count)
    print('serving', node.get_fully_qualified_name(), flush=True)
    rclpy.spin(node)
""")

CLIENT = textwrap.dedent("""
    import sys
    import rclpy
    from rclpy.action import ActionClient
    from rclpy.node import Node
    from test_msgs.action import Fibonacci
    from test_msgs.srv import BasicTypes
    from colcon_robmosys.devtools.system import answered

    rclpy.init(args=sys.argv)
    node = Node('unnamed')
    client = node.create_client(BasicTypes, 'qSum')
    assert client.wait_for_service(timeout_sec=30), 'no service'
    answer = answered(client, BasicTypes.Request(int32_value=41), node, timeout=30)
    print('answer', answer.int32_value, flush=True)
    actions = ActionClient(node, Fibonacci, 'aFibonacci')
    assert actions.wait_for_server(timeout_sec=30), 'no action server'
    goal = actions.send_goal_async(Fibonacci.Goal(order=4))
    rclpy.spin_until_future_complete(node, goal, timeout_sec=30)
    result = goal.result().get_result_async()
    rclpy.spin_until_future_complete(node, result, timeout_sec=30)
    print('result', list(result.result().result.sequence), flush=True)
""")


def test_service_and_action_names_are_remapped_as_one(tmp_path, domain_id):
    (tmp_path / 'robmosys.yaml').write_text(MODEL)
    result = load_workspace([tmp_path / 'robmosys.yaml'], InterfaceIndex([Path(sys.prefix)]))
    result.raise_errors()
    plan = plan_package(result.workspace, 'remap_system')
    nodes = {n.instance: NodeLaunch(
        package=n.package, executable=n.executable, name=n.name,
        namespace=n.namespace, remappings=n.remappings, params_files=())
        for n in plan.summary['nodes']}
    # an action's own rule (Kilted), then one per service and topic of it (Jazzy)
    parts = [f'_action/{part}' for part in
             ('send_goal', 'cancel_goal', 'get_result', 'feedback', 'status')]
    assert nodes['server'].remappings == (
        ('qAdd', '/robot/server/qAdd'), ('aCount', '/robot/count'),
        *((f'aCount/{part}', f'/robot/count/{part}') for part in parts))
    assert set(nodes['client'].remappings) == {
        ('qSum', '/robot/server/qAdd'), ('aFibonacci', '/robot/count'),
        *((f'aFibonacci/{part}', f'/robot/count/{part}') for part in parts)}
    env = loopback_env(domain_id)
    with background([sys.executable, '-c', SERVER, *nodes['server'].ros_args()],
                    env=env) as server:
        assert wait_until(lambda: 'serving /robot/server' in server.output(), timeout=30), \
            server.output()
        client = run([sys.executable, '-c', CLIENT, *nodes['client'].ros_args()],
                     env=env, timeout=120)
        served = server.output()
    assert client.returncode == 0, client.stdout + client.stderr + served
    assert client.stdout.split('\n')[:2] == ['answer 42', 'result [0, 1, 2, 3]']
