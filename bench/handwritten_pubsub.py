# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""A hand-written rclpy lifecycle publisher/subscriber pair: the reference of bench_runtime.

It does what the generated pair of ``bench_runtime.py`` does, the way one would write
it by hand: the same message type (std_msgs/msg/Header), QoS, period, callback groups,
entities created on configure, the timer started on activate; the same code in the
timer and the subscription; the same report. The executor is the second argument:
``multi-threaded`` (the default: rclpy's MultiThreadedExecutor), ``events``
(rclpy.experimental.EventsExecutor) or ``default`` (``rclpy.spin(node)``, rclpy's
SingleThreadedExecutor, as the ROS 2 tutorials write it).

    python handwritten_pubsub.py talker|listener [EXECUTOR] --ros-args -p burst:=100 ...
"""

from __future__ import annotations

import json
import sys
import time

import rclpy
from rclpy.callback_groups import MutuallyExclusiveCallbackGroup
from rclpy.executors import ExternalShutdownException, MultiThreadedExecutor
from rclpy.lifecycle import LifecycleNode, LifecyclePublisher, LifecycleState
from rclpy.lifecycle import TransitionCallbackReturn
from rclpy.qos import (
    DurabilityPolicy, HistoryPolicy, LivelinessPolicy, QoSProfile, ReliabilityPolicy)
from rclpy.subscription import Subscription
from rclpy.task import Future
from rclpy.timer import Timer
from std_msgs.msg import Header

PERIOD = 0.01
QOS = QoSProfile(history=HistoryPolicy.KEEP_LAST, depth=10,
                 reliability=ReliabilityPolicy.RELIABLE,
                 durability=DurabilityPolicy.VOLATILE,
                 liveliness=LivelinessPolicy.AUTOMATIC)


class Talker(LifecycleNode):
    """Publishes ``burst`` stamped headers every PERIOD seconds while active."""

    def __init__(self) -> None:
        super().__init__('Talker')
        self.declare_parameter('burst', 1)
        self.declare_parameter('payload', 0)
        self._group = MutuallyExclusiveCallbackGroup()
        self.pSample: LifecyclePublisher[Header] | None = None
        self._timer: Timer | None = None
        self._active = False

    def on_configure(self, state: LifecycleState) -> TransitionCallbackReturn:
        """Create the publisher and the (stopped) timer."""
        self.pSample = self.create_lifecycle_publisher(Header, 'pSample', QOS)
        self._timer = self.create_timer(PERIOD, self._publish, callback_group=self._group,
                                        autostart=False)
        self.now_ns = time.time_ns
        self.burst = self.get_parameter('burst').value
        self.frame = 'x' * self.get_parameter('payload').value
        self.sent = 0
        self.first = self.last = 0
        return TransitionCallbackReturn.SUCCESS

    def on_activate(self, state: LifecycleState) -> TransitionCallbackReturn:
        """Start publishing."""
        result = super().on_activate(state)
        self._active = True
        assert self._timer is not None
        self._timer.reset()
        return result

    def on_deactivate(self, state: LifecycleState) -> TransitionCallbackReturn:
        """Stop publishing and report how much was sent."""
        self._active = False
        assert self._timer is not None
        self._timer.cancel()
        result = super().on_deactivate(state)
        print('BENCH talker ' + json.dumps(
            {'sent': self.sent, 'first': self.first, 'last': self.last}), flush=True)
        return result

    def on_cleanup(self, state: LifecycleState) -> TransitionCallbackReturn:
        """Release the publisher and the timer."""
        self._release()
        return TransitionCallbackReturn.SUCCESS

    def on_shutdown(self, state: LifecycleState) -> TransitionCallbackReturn:
        """Release the publisher and the timer."""
        self._release()
        return TransitionCallbackReturn.SUCCESS

    def _release(self) -> None:
        self._active = False
        if self._timer is not None:
            self.destroy_timer(self._timer)
            self._timer = None
        if self.pSample is not None:
            self.destroy_lifecycle_publisher(self.pSample)
            self.pSample = None

    def _publish(self) -> None:
        if not self._active or self.pSample is None:
            return
        for _ in range(self.burst):
            now = self.now_ns()
            message = Header(frame_id=self.frame)
            message.stamp.sec, message.stamp.nanosec = divmod(now, 1_000_000_000)
            self.pSample.publish(message)
        self.sent += self.burst
        self.first = self.first or now
        self.last = now


class Listener(LifecycleNode):
    """Records the latency of every header received while active, after a warm-up."""

    def __init__(self) -> None:
        super().__init__('Listener')
        self.declare_parameter('warmup', 0.5)
        self._group = MutuallyExclusiveCallbackGroup()
        self.rSample: Subscription[Header] | None = None
        self._active = False

    def on_configure(self, state: LifecycleState) -> TransitionCallbackReturn:
        """Create the subscription."""
        self.rSample = self.create_subscription(
            Header, 'rSample', self._receive, QOS, callback_group=self._group)
        self.now_ns = time.time_ns
        self.warmup_ns = int(self.get_parameter('warmup').value * 1e9)
        self.latencies: list[int] = []
        self.first = self.start = self.last = 0
        return TransitionCallbackReturn.SUCCESS

    def on_activate(self, state: LifecycleState) -> TransitionCallbackReturn:
        """Start receiving."""
        result = super().on_activate(state)
        self._active = True
        return result

    def on_deactivate(self, state: LifecycleState) -> TransitionCallbackReturn:
        """Stop receiving and report every latency measured."""
        self._active = False
        result = super().on_deactivate(state)
        print('BENCH listener ' + json.dumps(
            {'start': self.start, 'last': self.last, 'latencies': self.latencies}),
            flush=True)
        return result

    def on_cleanup(self, state: LifecycleState) -> TransitionCallbackReturn:
        """Release the subscription."""
        self._release()
        return TransitionCallbackReturn.SUCCESS

    def on_shutdown(self, state: LifecycleState) -> TransitionCallbackReturn:
        """Release the subscription."""
        self._release()
        return TransitionCallbackReturn.SUCCESS

    def _release(self) -> None:
        self._active = False
        if self.rSample is not None:
            self.destroy_subscription(self.rSample)
            self.rSample = None

    def _receive(self, message: Header) -> None:
        if not self._active:
            return
        now = self.now_ns()
        if not self.first:
            self.first = now
            print('BENCH listener first', flush=True)
        if now - self.first < self.warmup_ns:
            return
        self.start = self.start or now
        self.latencies.append(now - message.stamp.sec * 1_000_000_000 - message.stamp.nanosec)
        self.last = now


def main() -> None:
    """Spin the talker or the listener until SIGINT or SIGTERM, then shut down cleanly."""
    rclpy.init(args=sys.argv)
    node = {'talker': Talker, 'listener': Listener}[sys.argv[1]]()
    kind = sys.argv[2] if len(sys.argv) > 2 and sys.argv[2] != '--ros-args' else \
        'multi-threaded'
    if kind == 'default':
        try:
            rclpy.spin(node)
        except (KeyboardInterrupt, ExternalShutdownException):
            pass
        finally:
            node.destroy_node()
            rclpy.try_shutdown()
        return
    if kind == 'events':
        from rclpy.experimental import EventsExecutor
        executor = EventsExecutor()
    else:
        executor = MultiThreadedExecutor()
    executor.add_node(node)
    try:
        if kind == 'events':
            # an untimed spin() of the EventsExecutor of the ros-* wheels (rclpy
            # 7.1.6, 9.1.2) runs no callback: spun for an hour at a time
            while rclpy.ok():
                executor.spin_until_future_complete(Future(), timeout_sec=3600.0)
        else:
            executor.spin()
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    finally:
        executor.shutdown()
        node.destroy_node()
        rclpy.try_shutdown()


if __name__ == '__main__':
    main()
