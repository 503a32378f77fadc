# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""
Several Python instances of a system in one process (``processes: shared``).

``python -m robmosys_runtime.container DESCRIPTION PARAMS_FILE INSTANCE... [--ros-args ...]``
creates the node of each instance from its component's class, with the name,
namespace, remappings and parameter file the launch files would give it, and
spins them all on one executor (:func:`run_nodes`): the one the system names for
its shared processes, or the most capable one its instances need. Starting a
Python node costs most of its start-up time in the interpreter and rclpy:
one process for many instances starts a large system several times faster.
"""

from __future__ import annotations

import importlib
import json
import sys
from typing import Any, Callable, Dict, List, Optional

from rclpy.node import Node
from robmosys_runtime.main import run_nodes
from robmosys_runtime.processes import node_arguments


def node_factory(instance: Dict[str, Any], params_file: str) -> Callable[[], Node]:
    """Return what creates the node of an instance, as its own process would."""
    module_name, class_name = instance['python_class'].split(':')

    def create() -> Node:
        component = getattr(importlib.import_module(module_name), class_name)
        # node-local arguments only: a remapping of one instance is not another's
        return component(instance['name'], namespace=instance['namespace'] or None,
                         cli_args=['--ros-args', *node_arguments(instance, params_file)],
                         use_global_arguments=False)
    return create


def main(argv: Optional[List[str]] = None) -> int:
    """Run the instances named on the command line; return the exit status."""
    args = list(sys.argv[1:] if argv is None else argv)
    # what follows --ros-args is the process's (--log-level), for rclpy.init
    ros_arguments = args[args.index('--ros-args'):] if '--ros-args' in args else []
    description_file, params_file, *names = args[:len(args) - len(ros_arguments)]
    with open(description_file, encoding='utf-8') as stream:
        description = json.load(stream)
    instances = {i['instance']: i for i in description['instances']}
    unknown = [n for n in names if n not in instances or not instances[n].get('python_class')]
    if unknown or not names:
        print(f"container: error: not Python instances of the system: {', '.join(unknown)}"
              if unknown else 'container: error: no instance named', file=sys.stderr)
        return 2
    return run_nodes([node_factory(instances[n], params_file) for n in names],
                     executor_name=description.get('executors', {}).get('python'),
                     args=['container', *ros_arguments] if ros_arguments else None)


if __name__ == '__main__':
    sys.exit(main())
