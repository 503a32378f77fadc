# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""A fake ament prefix: the interfaces a ROS 2 install would provide to the model tests."""

from __future__ import annotations

from pathlib import Path

from colcon_robmosys.check.index import InterfaceIndex

#: The installed interfaces, as far as the test models use them.
INSTALLED = {
    'std_msgs': ['msg/Header.msg', 'msg/String.msg'],
    'geometry_msgs': ['msg/Pose.msg'],
    'example_interfaces': ['srv/AddTwoInts.srv', 'action/Fibonacci.action'],
    'builtin_interfaces': ['msg/Time.msg'],
}


#: The standard messages the example workspace uses besides INSTALLED (the
#: dummy_robot example): not in INSTALLED, where the corpus has them missing.
EXAMPLE_EXTRA = {
    'sensor_msgs': ['msg/JointState.msg', 'msg/LaserScan.msg'],
    'nav_msgs': ['msg/OccupancyGrid.msg'],
}


def fake_ament_index(prefix: Path, extra: dict[str, list[str]] | None = None
                     ) -> InterfaceIndex:
    """Lay out INSTALLED (and extra) as an ament prefix under ``prefix``; return its index."""
    markers = prefix / 'share' / 'ament_index' / 'resource_index' / 'packages'
    markers.mkdir(parents=True)
    for package, files in {**INSTALLED, **(extra or {})}.items():
        (markers / package).write_text('')
        for name in files:
            path = prefix / 'share' / package / name
            path.parent.mkdir(parents=True, exist_ok=True)
            path.write_text('')
    return InterfaceIndex([prefix])
