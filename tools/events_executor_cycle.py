# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""Check that rclpy's EventsExecutor survives a lifecycle node cleaned up and configured again.

Plain rclpy, no robmosys_runtime: the reproduction of issue 28 (docs/model-format.md,
Executors). A lifecycle node spun by ``rclpy.experimental.EventsExecutor`` makes its
entities on configure and destroys them on cleanup, as a generated component does
with its ports; a peer node in another context of the same process keeps them busy
and drives the transitions over ``/n/change_state``. Two kinds of entity:

``action``
    an action client whose goal receives feedback every millisecond: a Waitable.
    rclpy 7.1.6 (Jazzy) and 9.1.2 (Kilted) die of a segmentation fault within a few
    cycles: an event queued for the client when the executor unregisters it holds
    the last reference to the executor's ``ScopedWith`` of its wait set, and is
    destroyed on the spinning thread, which does not hold the GIL.
``service``
    a subscription and a service under a flood of messages and requests (no
    Waitable but their QoS event handlers, which see no event here). A request
    queued before the cleanup is answered after it, on the destroyed service:
    ``send_response`` raises InvalidHandle out of the executor's spin.

Run it with the venv whose rclpy to check (``.venv/bin/python tools/events_executor_cycle.py``,
``.venv-jazzy/bin/python ...``). It prints one line and exits 0 when the node went
through every cycle, 1 when the process died or stopped answering. The node runs in
a child process, on loopback with a ROS_DOMAIN_ID of its own, under a timeout.
"""

from __future__ import annotations

import argparse
from importlib import metadata
import os
from pathlib import Path
import signal
import subprocess
import sys
import threading
import time
from typing import Any, List, Optional

#: seconds a transition or a first message may take on a loaded machine
WAIT = 20.0


def _child(kind: str, cycles: int) -> int:
    """Run the node and its peer; print a line per cycle; return 0 after every cycle."""
    import rclpy
    from rclpy.action import ActionClient, ActionServer
    from rclpy.executors import MultiThreadedExecutor
    from rclpy.experimental import EventsExecutor
    from rclpy.lifecycle import LifecycleNode, LifecycleState, TransitionCallbackReturn
    from rclpy.task import Future
    from lifecycle_msgs.msg import Transition
    from lifecycle_msgs.srv import ChangeState
    from std_msgs.msg import Int32
    from std_srvs.srv import Empty
    from test_msgs.action import Fibonacci

    class Cycled(LifecycleNode):
        def __init__(self) -> None:
            super().__init__('n')
            self.received = 0
            self.entities: List[Any] = []

        def on_configure(self, state: LifecycleState) -> TransitionCallbackReturn:
            if kind == 'action':
                client = ActionClient(self, Fibonacci, 'fib')
                client.send_goal_async(Fibonacci.Goal(order=1), feedback_callback=self.got)
                self.entities = [client]
            else:
                self.entities = [self.create_subscription(Int32, 'flood', self.got, 10),
                                 self.create_service(Empty, 'ask', lambda q, r: r)]
            return TransitionCallbackReturn.SUCCESS

        def got(self, message: Any) -> None:
            self.received += 1

        def on_cleanup(self, state: LifecycleState) -> TransitionCallbackReturn:
            for entity in self.entities:
                if kind == 'action':
                    entity.destroy()
                elif hasattr(entity, 'srv_type'):
                    self.destroy_service(entity)
                else:
                    self.destroy_subscription(entity)
            self.entities = []
            return TransitionCallbackReturn.SUCCESS

    rclpy.init()
    node = Cycled()
    executor = EventsExecutor()
    executor.add_node(node)
    # an untimed spin() of these wheels runs no callback (docs/model-format.md)
    threading.Thread(target=executor.spin_until_future_complete,
                     args=(Future(),), kwargs={'timeout_sec': 3600.0}, daemon=True).start()

    peer_context = rclpy.Context()
    rclpy.init(context=peer_context)
    peer = rclpy.create_node('peer', context=peer_context)
    newest: List[Any] = []

    def execute(goal_handle: Any) -> Any:
        newest[:] = [goal_handle]
        while peer_context.ok() and goal_handle.is_active and newest[0] is goal_handle:
            goal_handle.publish_feedback(Fibonacci.Feedback(sequence=[1]))
            time.sleep(0.001)
        return Fibonacci.Result()

    ActionServer(peer, Fibonacci, 'fib', execute)
    publisher = peer.create_publisher(Int32, 'flood', 10)
    asker = peer.create_client(Empty, 'ask')

    def flood() -> None:
        while peer_context.ok():
            publisher.publish(Int32(data=1))
            if asker.service_is_ready():
                asker.call_async(Empty.Request())
            time.sleep(0.0005)
    if kind == 'service':
        threading.Thread(target=flood, daemon=True).start()
    peer_executor = MultiThreadedExecutor(context=peer_context)
    peer_executor.add_node(peer)
    threading.Thread(target=peer_executor.spin, daemon=True).start()
    change_state = peer.create_client(ChangeState, '/n/change_state')
    if not change_state.wait_for_service(timeout_sec=WAIT):
        print('no /n/change_state', flush=True)
        return 1

    def change(transition: int) -> bool:
        answer = change_state.call_async(ChangeState.Request(
            transition=Transition(id=transition)))
        deadline = time.monotonic() + WAIT
        while not answer.done() and time.monotonic() < deadline:
            time.sleep(0.01)
        return answer.done() and answer.result().success

    for cycle in range(cycles):
        if not change(Transition.TRANSITION_CONFIGURE):
            print(f'cycle {cycle}: configure not answered', flush=True)
            return 1
        before = node.received
        deadline = time.monotonic() + WAIT
        while node.received == before and time.monotonic() < deadline:
            time.sleep(0.01)
        if not change(Transition.TRANSITION_CLEANUP):
            print(f'cycle {cycle}: cleanup not answered', flush=True)
            return 1
        print(f'cycle {cycle}: configured, received, cleaned up', flush=True)
    return 0


def _rclpy_version() -> str:
    for distribution in ('ros-rclpy', 'rclpy'):
        try:
            return f'{distribution} {metadata.version(distribution)}'
        except metadata.PackageNotFoundError:
            continue
    return 'rclpy'


def main(argv: Optional[List[str]] = None) -> int:
    """Run the node in a child process on loopback; report how it ended."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--entities', choices=('action', 'service'), default='action',
                        help='what the node makes on configure (default: action)')
    parser.add_argument('--cycles', type=int, default=20)
    parser.add_argument('--child', action='store_true', help=argparse.SUPPRESS)
    args = parser.parse_args(argv)
    if args.child:
        code = _child(args.entities, args.cycles)
        # the peer's threads still spin: the interpreter's teardown would race them
        sys.stdout.flush()
        os._exit(code)
    sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
    from colcon_robmosys.devtools.ros_env import free_domain_id, loopback_env, run
    version = _rclpy_version()
    command = [sys.executable, __file__, '--child', '--entities', args.entities,
               '--cycles', str(args.cycles)]
    try:
        result = run(command, env=loopback_env(free_domain_id()),
                     timeout=60 + args.cycles * 3 * WAIT)
    except subprocess.TimeoutExpired as timeout:
        print(f'{args.entities}: timed out\n{timeout.stdout}{timeout.stderr}')
        return 1
    done = result.stdout.count(': configured, received, cleaned up')
    if result.returncode == 0:
        print(f'{args.entities}: {done} cycles on the EventsExecutor of {version}')
        return 0
    if result.returncode < 0:
        ended = f'killed by {signal.Signals(-result.returncode).name}'
    else:
        ended = f'exit status {result.returncode}'
    print(f'{args.entities}: {ended} after {done} of {args.cycles} cycles '
          f'({version})\n{result.stdout}{result.stderr}')
    return 1


if __name__ == '__main__':
    sys.exit(main())
