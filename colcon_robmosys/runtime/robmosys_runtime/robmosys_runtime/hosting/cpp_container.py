# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""
Several C++ instances of a system in one process (``processes: shared``).

``python -m robmosys_runtime.hosting.cpp_container [--activate [--report-fd FD |
--report-file FILE]] DESCRIPTION PARAMS_FILE INSTANCE... [--ros-args ...]``
takes what :mod:`robmosys_runtime.hosting.container` takes, for the C++ instances of
one host, and becomes (``exec``, the same process) the system package's
component container (``lib/<system>/component_container``: robmosys_runtime's
``src/component_container.cpp``, which the package builds) with everything it
needs on its command line, counted: the C++ program parses no JSON and no
file. The container is rclcpp_components' (its node,
``<system>_container`` or ``<system>_<host>_container``, serves
``_container/load_node``), and makes the node of each instance itself with its
component's factory, with the name, namespace, remappings and parameter file
the instance's own process would have. With ``--activate`` it brings the
managed ones up in the model's order and tells the manager what it brought up
(:mod:`robmosys_runtime.hosting.told`), as the shared Python process does: the
manager neither loads each node through the container's service nor takes it
through two transitions of its lifecycle services (what it added to the floor
of 50 C++ instances: 1.64x to 1.73x, issue 28).
"""

from __future__ import annotations

import os
import sys
from typing import Any, Dict, List, Optional

from robmosys_runtime.hosting.processes import container_program, node_arguments, SharedArguments
from robmosys_runtime.hosting.told import shared_start


def container_node(package: str, host: str = '') -> str:
    """
    Return the node name of the component container of a system's C++ instances.

    :param host: the host whose instances it runs ('' for the manager's host):
      each host has a container of its own, and node names are unique across hosts
    """
    return f'{package}_{host}_container' if host else f'{package}_container'


def program_arguments(description: Dict[str, Any], args: SharedArguments,
                      program: str) -> List[str]:
    """Return the command line of the component container (``program``) for ``args``."""
    instances = {i['instance']: i for i in description['instances']}
    chosen = [instances[n] for n in args.names]
    counted: List[str] = [str(len(chosen))]
    for instance in chosen:
        # one that comes after an instance of another process is left to the manager
        after = list(instance.get('after', ()))
        node = ['-r', f"__node:={instance['name']}"]
        if instance['namespace']:
            node += ['-r', f"__ns:={instance['namespace']}"]
        node += node_arguments(instance, args.params_file)
        managed = instance.get('managed') and instance.get('lifecycle', True)
        counted += [instance['instance'], instance['package'], instance['plugin'],
                    '1' if managed else '0', str(len(after)), *after, str(len(node)), *node]
    host = chosen[0].get('host', '')
    container = ['-r', f"__node:={container_node(description['package'], host)}"]
    if description.get('namespace'):
        container += ['-r', f"__ns:={description['namespace']}"]
    return [
        program,
        description.get('executors', {}).get('cpp', 'multi-threaded'),
        # a blocking call of one node never starves the thread of another's answer
        str(sum(int(i.get('threads', 1)) for i in chosen)),
        '1' if args.activate else '0',
        str(-1 if args.report_fd is None else args.report_fd),
        args.report_file or '',
        *counted,
        '--ros-args', *container, *args.ros_arguments[1:]]


def main(argv: Optional[List[str]] = None) -> int:
    """Become the component container of the instances named; return an exit status if not."""
    # exec keeps the pid that shared_start writes for the manager
    started = shared_start(list(sys.argv[1:] if argv is None else argv), 'cpp_container',
                           'plugin', 'C++')
    if started is None:
        return 2
    args, description, _ = started
    command = program_arguments(description, args, container_program(description['package']))
    sys.stdout.flush()
    try:
        os.execv(command[0], command)
    except OSError as error:
        print(f"{command[0]}: error: {error.strerror} (the package '{description['package']}' "
              'was built without rclcpp_components?)', file=sys.stderr)
    return 1


if __name__ == '__main__':
    sys.exit(main())
