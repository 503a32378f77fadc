# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""The floor of bench_bringup.py: a system's nodes made and activated in one process, no manager.

    python bringup_floor.py DESCRIPTION PARAMS_FILE

Makes the node of every instance of a system's description (``bringup.json``)
as the shared process does (:mod:`robmosys_runtime.hosting.container`), then configures
and activates each in turn through rclpy's own transitions: no lifecycle
service, no DDS discovery, no other process. Prints ``floor: <N> of <N> active``
once done. That is what these N rclpy lifecycle nodes cost to be up in one
process, whatever drives them: no bring-up of them can be faster, and
bench_bringup.py compares its bring-ups with it.
"""

from __future__ import annotations

import json
import sys
from typing import Sequence

import rclpy
from rclpy.lifecycle import TransitionCallbackReturn
from robmosys_runtime.hosting.container import node_factory


def main(argv: Sequence[str]) -> int:
    """Make and activate the nodes of a description; return 0 if all are active."""
    description_file, params_file = argv
    with open(description_file, encoding='utf-8') as stream:
        instances = json.load(stream)['instances']
    rclpy.init()
    try:
        nodes = [node_factory(instance, params_file)() for instance in instances]
        active = sum(node.trigger_configure() == TransitionCallbackReturn.SUCCESS
                     and node.trigger_activate() == TransitionCallbackReturn.SUCCESS
                     for node in nodes)
        print(f'floor: {active} of {len(nodes)} active', flush=True)
        for node in nodes:
            node.destroy_node()
    finally:
        rclpy.try_shutdown()
    return 0 if active == len(nodes) else 1


if __name__ == '__main__':
    raise SystemExit(main(sys.argv[1:]))
