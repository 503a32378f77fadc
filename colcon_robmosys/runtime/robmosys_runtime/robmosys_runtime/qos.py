# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""
QoS at launch time: the QoS of a port is a default that parameters override.

The publishers and subscriptions of a component take ROS 2's own QoS overrides,
read-only parameters ``qos_overrides.<topic>.<publisher|subscription>.<policy>``
declared when the port is created (on configure). A configure after a cleanup
finds them declared, and keeps their values (rclpy and rclcpp of Jazzy and
Kilted do so: tests/test_qos_launch.py runs it).
"""

import copy
from typing import Any, Dict

from rclpy.qos import QoSPolicyKind, QoSProfile
from rclpy.qos_overriding_options import QoSOverridingOptions

#: Every policy of the model's QoS; avoid_ros_namespace_conventions is left
#: out, as it would change the name a system remaps the port to.
OVERRIDABLE = QoSOverridingOptions([
    QoSPolicyKind.HISTORY, QoSPolicyKind.DEPTH, QoSPolicyKind.RELIABILITY,
    QoSPolicyKind.DURABILITY, QoSPolicyKind.DEADLINE, QoSPolicyKind.LIFESPAN,
    QoSPolicyKind.LIVELINESS, QoSPolicyKind.LIVELINESS_LEASE_DURATION])


def overridable(qos: QoSProfile) -> Dict[str, Any]:
    """
    Return the arguments of create_publisher or create_subscription for a port's QoS.

    rclpy applies the overrides to the profile it is given: the port gets a
    copy of the component's, which all the nodes of a process share.
    """
    return {'qos_profile': copy.copy(qos), 'qos_overriding_options': OVERRIDABLE}
