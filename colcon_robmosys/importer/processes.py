# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

"""Which package and executable run a node: what the processes of this host show.

The ROS graph does not say which executable runs a node, nor the names a node
gives its topics before remapping. A node started by ``ros2 run`` or a launch
file on this host shows both in its command line:
``.../lib/<package>/<executable> --ros-args -r __node:=<name> -r <from>:=<to>``.
A node is matched to a process by its name and namespace, and only where
exactly one process matches; a node of another host, or started some other
way, stays unknown. Processes of another ROS domain on this host are not in
the graph read, and are not candidates (a node of the same name there would
make the match ambiguous).
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from pathlib import Path


@dataclass(frozen=True)
class NodeProcess:
    """The executable of a process, and the remappings it was given."""

    package: str
    executable: str
    #: 'cpp' for a compiled executable, 'python' for a script
    language: str
    #: the node's name and namespace the process sets, '' where it sets none
    node: str = ''
    namespace: str = ''
    #: from -> to
    remappings: dict[str, str] = field(default_factory=dict)

    @property
    def fqn(self) -> str:
        """Return the fully qualified name of its node (the executable's name if it sets none)."""
        namespace = self.namespace.strip('/')
        node = self.node or self.executable
        return f'/{namespace}/{node}' if namespace else f'/{node}'

    @property
    def named_node(self) -> str:
        """Return the fully qualified name its command line gives its node, '' if none."""
        return self.fqn if self.node else ''


def node_processes(domain: str, proc: Path = Path('/proc')) -> list[NodeProcess]:
    """Return the processes of this host that run an executable of a ROS package.

    :param domain: the ROS domain id whose processes count ('0' where the
      environment sets none, as in ROS 2)
    """
    found = []
    for entry in proc.iterdir() if proc.is_dir() else ():
        if not entry.name.isdigit():
            continue
        try:
            argv = (entry / 'cmdline').read_bytes().decode('utf-8', 'replace').split('\0')
        except OSError:
            continue  # gone, or not ours to read
        process = parse_command_line(argv)
        if process is not None and _domain_of(entry) in (domain_id(domain), None):
            found.append(process)
    return found


def domain_id(text: str) -> str:
    """Return a ROS_DOMAIN_ID as ROS 2 reads it: empty or unset is 0."""
    return text.strip() or '0'


def _domain_of(entry: Path) -> str | None:
    """Return the ROS domain id of a process, None if its environment is not readable."""
    try:
        environ = (entry / 'environ').read_bytes().split(b'\0')
    except OSError:
        return None
    value = next((line[len(b'ROS_DOMAIN_ID='):] for line in environ
                  if line.startswith(b'ROS_DOMAIN_ID=')), b'')
    return domain_id(value.decode('utf-8', 'replace'))


def parse_command_line(argv: list[str]) -> NodeProcess | None:
    """Return what a command line runs, None if no executable of a package."""
    # a script runs as 'python3 <script>': the executable is one of the first two
    executable = next((Path(arg) for arg in argv[:2]
                       if Path(arg).parent.parent.name == 'lib' and Path(arg).is_file()), None)
    if executable is None:
        return None
    remappings: dict[str, str] = {}
    in_ros_args = False
    for index, arg in enumerate(argv):
        if arg == '--ros-args':
            in_ros_args = True
        elif arg == '--':
            in_ros_args = False
        elif in_ros_args and arg in ('-r', '--remap') and index + 1 < len(argv):
            source, _, target = argv[index + 1].partition(':=')
            # a rule for another node (node:from:=to) is not this node's
            if target and ':' not in source:
                remappings[source] = target
    try:
        compiled = executable.read_bytes()[:4] == b'\x7fELF'
    except OSError:
        return None
    return NodeProcess(
        executable.parent.name, executable.name, 'cpp' if compiled else 'python',
        remappings.pop('__node', remappings.pop('__name', '')),
        remappings.pop('__ns', ''), remappings)


def process_of(processes: list[NodeProcess], name: str, namespace: str) -> NodeProcess | None:
    """Return the process that runs a node, None if none or different ones could."""
    fqn = f"{namespace.rstrip('/')}/{name}"
    candidates = [process for process in processes if process.fqn == fqn]
    # the same node twice (two launches of it): what they agree on is known
    if not candidates or len({(p.package, p.executable, p.language)
                              for p in candidates}) > 1:
        return None
    if any(process.remappings != candidates[0].remappings for process in candidates):
        return replace(candidates[0], remappings={})
    return candidates[0]
