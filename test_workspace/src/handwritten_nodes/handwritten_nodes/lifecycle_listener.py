# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""A lifecycle rclpy node, written by hand: logs what arrives on 'heard' while active."""

import rclpy
from rclpy.executors import ExternalShutdownException
from rclpy.lifecycle import LifecycleNode, TransitionCallbackReturn
from std_msgs.msg import String


class LifecycleListener(LifecycleNode):
    """Subscribe to heard from configure to cleanup; log it while active."""

    def __init__(self):
        super().__init__('lifecycle_listener')
        self.subscription = None
        self.active = False

    def on_configure(self, state):
        """Create the subscription."""
        self.subscription = self.create_subscription(String, 'heard', self.hear, 10)
        return TransitionCallbackReturn.SUCCESS

    def on_activate(self, state):
        """Start logging."""
        self.active = True
        return super().on_activate(state)

    def on_deactivate(self, state):
        """Stop logging."""
        self.active = False
        return super().on_deactivate(state)

    def on_cleanup(self, state):
        """Drop the subscription."""
        self.destroy_subscription(self.subscription)
        self.subscription = None
        return TransitionCallbackReturn.SUCCESS

    def hear(self, message):
        """Log a message, while active."""
        if self.active:
            self.get_logger().info(f'heard: {message.data}')


def main(args=None):
    """Spin the listener until Ctrl-C."""
    rclpy.init(args=args)
    node = LifecycleListener()
    try:
        rclpy.spin(node)
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    finally:
        node.destroy_node()
        rclpy.try_shutdown()
