# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""A plain rclpy node, written by hand: says hello on 'chatter' five times a second."""

import rclpy
from rclpy.executors import ExternalShutdownException
from rclpy.node import Node
from std_msgs.msg import String


class Talker(Node):
    """Publish 'hello N' on chatter."""

    def __init__(self):
        super().__init__('talker')
        self.count = 0
        self.publisher = self.create_publisher(String, 'chatter', 10)
        self.create_timer(0.2, self.say)

    def say(self):
        """Publish the next greeting."""
        self.count += 1
        self.publisher.publish(String(data=f'hello {self.count}'))


def main(args=None):
    """Spin the talker until Ctrl-C."""
    rclpy.init(args=args)
    node = Talker()
    try:
        rclpy.spin(node)
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    finally:
        node.destroy_node()
        rclpy.try_shutdown()
