# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""Benchmark 7 (issue 42): a mode switch of the system manager, against its steps done by hand.

Runs ``mode_robot_system`` of test_workspace (built: ``--install``, default
test_workspace/install; six Python instances, three modes, a subsystem with two)
under ``ros2 run mode_robot_system bringup`` (watch off), and times, in the same
run and alternating them, ``--rounds`` times each:

- ``manager``: ``~/set_mode/<B>`` then ``~/set_mode/<A>`` (``--modes A B``, default
  cruising and mapping: the largest switch of the model, 8 steps each way), each from
  the request to its answer;
- ``direct``: the same steps made from this process with rclpy, as a user would
  without the manager: ``change_state`` of each instance the manager deactivates
  and activates, in its order, each waiting for its answer, and one
  ``set_parameters`` per node with the same values, every node's at once, as the
  manager sends them; clients made and matched beforehand.

The direct steps are those the manager's answers listed, so both do the same
transitions and calls; both end in A, so the manager's view stays true. Prints the
fastest of each, their spread and the ratio manager / direct (goal of issue 42: at
most 1.2x), "met" or "NOT met", and for scale the round trip of a call of the
manager that does nothing much (``~/report``), which every switch pays once.

    .venv/bin/python bench/bench_modes.py
"""

from __future__ import annotations

import argparse
import json
import os
from pathlib import Path
import signal
import subprocess
import sys
import time
from typing import Any, Sequence

from benchlib import best, print_end, print_machine, ratio, spread, table
from colcon_robmosys.devtools import ros_env

ROOT = Path(__file__).resolve().parent.parent
SYSTEM = 'mode_robot_system'
#: the goal: a switch takes at most this many times its steps done directly
GOAL = 1.2


class Direct:
    """The steps of a switch made with rclpy from this process, clients ready."""

    def __init__(self, node: Any, executor: Any, description: dict[str, Any]) -> None:
        from lifecycle_msgs.srv import ChangeState
        from rcl_interfaces.srv import SetParameters
        self.node, self.executor = node, executor
        self.fqn = {i['instance']: i['fqn'] for i in description['instances']}
        self.change = {n: node.create_client(ChangeState, f'{f}/change_state')
                       for n, f in self.fqn.items()}
        self.set = {n: node.create_client(SetParameters, f'{f}/set_parameters')
                    for n, f in self.fqn.items()}
        for client in [*self.change.values(), *self.set.values()]:
            if not client.wait_for_service(timeout_sec=30):
                raise RuntimeError(f'{client.srv_name} did not appear')

    def call(self, client: Any, request: Any) -> Any:
        """Call a service; return its answer."""
        future = client.call_async(request)
        self.executor.spin_until_future_complete(future, timeout_sec=30)
        if not future.done():
            raise RuntimeError(f'{client.srv_name} did not answer')
        return future.result()

    def run(self, steps: list[str], values: dict[str, dict[str, Any]]) -> None:
        """Make the steps a switch listed (``deactivate x``, ``set x: a, b``, ``activate x``)."""
        from lifecycle_msgs.msg import Transition
        from lifecycle_msgs.srv import ChangeState
        from rcl_interfaces.srv import SetParameters
        from rclpy.parameter import Parameter
        setting = []
        for step in steps + ['']:
            verb, _, rest = step.partition(' ')
            if verb == 'set':
                name, _, names = rest.partition(': ')
                setting.append(self.set[name].call_async(SetParameters.Request(parameters=[
                    Parameter(p, value=values[name][p]).to_parameter_msg()
                    for p in names.split(', ')])))
                continue
            # the values of several nodes at once, as the manager sets them
            for future in setting:
                self.executor.spin_until_future_complete(future, timeout_sec=30)
                assert all(r.successful for r in future.result().results), steps
            setting = []
            if verb in ('activate', 'deactivate'):
                request = ChangeState.Request()
                request.transition = Transition(id=Transition.TRANSITION_ACTIVATE if
                                                verb == 'activate' else
                                                Transition.TRANSITION_DEACTIVATE)
                assert self.call(self.change[rest], request).success, step


def median_ratio(manager: list[float], direct: list[float]) -> float:
    """Return the median of manager / direct of each round (made one after the other)."""
    ratios = sorted(m / d for m, d in zip(manager, direct))
    return ratios[len(ratios) // 2]


def main(argv: Sequence[str] | None = None) -> int:
    """Run the benchmark; return the exit status."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--install', type=Path, default=ROOT / 'test_workspace' / 'install')
    parser.add_argument('--rounds', type=int, default=10)
    parser.add_argument('--modes', nargs=2, default=['cruising', 'mapping'], metavar='MODE')
    args = parser.parse_args(argv)
    print_machine('bench_modes: a mode switch vs its steps made directly with rclpy')
    share = args.install / SYSTEM / 'share' / SYSTEM
    description = json.loads((share / 'bringup.json').read_text())
    modes = {m['name']: m for m in description['modes']}
    domain_id = ros_env.free_domain_id()
    env = ros_env.workspace_env(args.install, ros_env.loopback_env(domain_id))
    executable = args.install / SYSTEM / 'lib' / SYSTEM / 'bringup'
    bringup = subprocess.Popen([sys.executable, str(executable), '--check-period', '0'],
                               env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                               text=True, start_new_session=True)
    os.environ.update(env)
    import rclpy
    from rclpy.executors import SingleThreadedExecutor
    from std_srvs.srv import Trigger
    rclpy.init()
    node = rclpy.create_node('bench_modes')
    executor = SingleThreadedExecutor()
    executor.add_node(node)
    manager, direct, call = [], [], []
    first, second = args.modes
    try:
        line = ''
        while 'managed instances active' not in line:
            line = bringup.stdout.readline() if bringup.stdout else ''
            if not line and bringup.poll() is not None:
                raise RuntimeError('bringup ended before the system was up')
        switch: dict[str, Any] = {
            m: node.create_client(Trigger, f'/{SYSTEM}_bringup/set_mode/{m}') for m in args.modes}
        switch['report'] = node.create_client(Trigger, f'/{SYSTEM}_bringup/report')
        for client in switch.values():
            assert client.wait_for_service(timeout_sec=30)
        hand = Direct(node, executor, description)

        def set_mode(mode: str) -> tuple[float, list[str]]:
            start = time.perf_counter()
            answer = hand.call(switch[mode], Trigger.Request())
            took = time.perf_counter() - start
            assert answer.success, answer.message
            return took, answer.message.splitlines()[:-1]

        # the steps, as the manager makes them (the first switch also matches its clients)
        set_mode(first)
        _, there = set_mode(second)
        _, back = set_mode(first)
        for _ in range(args.rounds):
            took = [set_mode(second)[0], set_mode(first)[0]]
            manager.append(sum(took))
            time.sleep(0.3)
            start = time.perf_counter()
            hand.run(there, modes[second]['values'])
            hand.run(back, modes[first]['values'])
            direct.append(time.perf_counter() - start)
            time.sleep(0.3)
            start = time.perf_counter()
            hand.call(switch['report'], Trigger.Request())
            call.append(time.perf_counter() - start)
    finally:
        node.destroy_node()
        rclpy.try_shutdown()
        os.killpg(bringup.pid, signal.SIGINT)
        bringup.wait(timeout=60)
    print(f'steps there: {there}\nsteps back: {back}')
    print(table(['path', f'{first} -> {second} -> {first} (s)', 'spread'], [
        ['manager (~/set_mode)', f'{best(manager):.4f}', spread(manager)],
        ['direct (rclpy)', f'{best(direct):.4f}', spread(direct)],
        ['(a call of ~/report)', f'{best(call):.4f}', spread(call)]]))
    met = best(manager) <= GOAL * best(direct)
    print(f'manager / direct: {ratio(best(manager), best(direct))} (goal: at most {GOAL}x): '
          f"{'met' if met else 'NOT met'}")
    # the floor of a switch through a manager: the same calls, and asking it (twice a round)
    floor = best(direct) + 2 * best(call)
    print(f'manager / (direct + two calls of the manager): {ratio(best(manager), floor)}; '
          f'per round, median: {ratio(median_ratio(manager, direct), 1.0)}')
    print_end()
    return 0


if __name__ == '__main__':
    sys.exit(main())
