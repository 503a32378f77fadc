# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""A hand-written level sensor: an ordinary rclpy node that serves an event port."""

from example_msgs.action import LevelAbove
import rclpy
from rclpy.executors import ExternalShutdownException
from rclpy.node import Node
from rclpy.qos import qos_profile_sensor_data
from robmosys_runtime import EventServer


class HandLevelSensor(Node):
    """Measure a level that climbs from 0 to 19; notify it to the activations it reaches."""

    def __init__(self) -> None:
        super().__init__('hand_level_sensor')
        self.level = -1
        # the event port eLevel, as a generated component requires it: each
        # activation (a goal) names a threshold, each event is a level
        self.eLevel = EventServer(
            self, LevelAbove, 'eLevel', qos_profile_sensor_data,
            condition=lambda activation, event: event.level >= activation.threshold)
        self.timer = self.create_timer(0.05, self.measure)

    def measure(self) -> None:
        """Take the next level and notify it."""
        self.level = (self.level + 1) % 20
        notified = self.eLevel.fire(LevelAbove.Feedback(level=self.level))
        if notified:
            self.get_logger().info(f'level {self.level} notified to {notified}')

    def destroy_node(self) -> None:
        """End the activations, then the node."""
        self.eLevel.destroy()
        super().destroy_node()


def main(args=None) -> None:
    """Spin the sensor until SIGINT or SIGTERM."""
    rclpy.init(args=args)
    node = HandLevelSensor()
    try:
        rclpy.spin(node)
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    finally:
        node.destroy_node()
        rclpy.try_shutdown()


if __name__ == '__main__':
    main()
