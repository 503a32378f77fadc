# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""
Ask a running system from inside a host of devtools/netns.py; print the answer as JSON.

    ros_probe.py trigger /examples_system_bringup/report   -> {"success": .., "message": ..}
    ros_probe.py states /examples/sender /examples/receiver -> {"/examples/sender": "active"}

It runs in the host's environment (its domain, profile and discovery), with
the workspace sourced: a test process outside the namespaces reaches none of them.
An answer that does not come is null.
"""

import json
import sys

from lifecycle_msgs.srv import GetState
from robmosys_runtime.tools.smoke import Probe, spinning_node
from std_srvs.srv import Trigger


def main(what: str, names: list) -> dict:
    """Return the answers of a system to one question."""
    with spinning_node('hosts_probe') as node:
        probe = Probe(node)
        if what == 'trigger':
            answer = probe.call(names[0], Trigger, Trigger.Request(), 20.0)
            return None if answer is None else {'success': bool(answer.success),
                                                'message': answer.message}
        states = {}
        for fqn in names:
            answer = probe.call(f'{fqn}/get_state', GetState, GetState.Request(), 10.0)
            states[fqn] = None if answer is None else answer.current_state.label
        return states


if __name__ == '__main__':
    print(json.dumps(main(sys.argv[1], sys.argv[2:])), flush=True)
