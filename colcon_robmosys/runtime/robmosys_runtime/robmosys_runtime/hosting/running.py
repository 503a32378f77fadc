# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""
What of a system runs on this host already, before a ``bringup`` starts anything.

Read from /proc, at once: the ROS graph would need seconds of discovery
before it could say that a node is *not* there (a fresh participant took
0.9 to 3.1 s to see the nodes of one host, here), and every start would
wait for them. :func:`look` finds

- the processes a ``bringup`` of the system started (they carry :data:`MARK`
  in their environment: that ``bringup``'s pid and start time, the system,
  its namespace and host): those of one that still runs mean that a second
  one would start every instance twice; those of one that ended are on their
  way out (each got SIGTERM as it died, :mod:`.supervision`), and are waited
  for;
- another ``bringup`` of the system for the same host and namespace, by its
  command line (a launch file's ``bringup --attach`` too);
- a process that runs the node of an instance, started otherwise (by hand,
  a launch file left running): by the ``__node`` and ``__ns`` remappings of
  its command line (``ros2 run ... --ros-args -r __node:=x``, launch_ros'
  ``name=`` and ``namespace=``), by its executable where it renames no node
  (a generated component's node is named as its executable), or, for a
  shared process of the system, by the instances it names.

Only processes of this ROS domain and network namespace count (another
network namespace is another host), and only those whose environment this
process may read. A node whose name its program sets otherwise, or that
runs on another host, is not seen here.
"""

from __future__ import annotations

from dataclasses import dataclass, field
import json
import os
import signal
import time
from typing import Any, Callable, Dict, List, Optional, Sequence, Set

from robmosys_runtime.hosting.processes import shared_arguments

#: the environment variable that marks the processes a bringup started
MARK = 'ROBMOSYS_BRINGUP'


@dataclass
class Found:
    """What of a system runs on this host already."""

    #: another bringup of the system for the same host and namespace
    bringups: List[int] = field(default_factory=list)
    #: processes that a bringup of the system which ended left (ending)
    left: List[int] = field(default_factory=list)
    #: fully qualified node name -> a process that runs it, started otherwise
    nodes: Dict[str, int] = field(default_factory=dict)


def mark(package: str, namespace: str, host: str) -> str:
    """Return the value of :data:`MARK` for the processes this process starts."""
    return json.dumps([os.getpid(), _start_time(os.getpid()), package, namespace or '',
                       host or ''])


def look(description: Dict[str, Any], host: str) -> Found:
    """Return what of a system (its namespace, one host's part) runs here already."""
    package = description['package']
    namespace = description.get('namespace') or ''
    found = Found()
    own = _ancestors()
    net = _net('self')
    domain = _domain(os.environ)
    for entry in os.listdir('/proc'):
        if not entry.isdigit() or int(entry) in own:
            continue
        pid = int(entry)
        environ = _environ(pid)
        if environ is None or _domain(environ) != domain or _net(pid) != net:
            continue
        argv = _argv(pid)
        marked = _marked(environ.get(MARK, ''))
        if marked is not None and marked[2:] == [package, namespace, host]:
            if marked[1] is not None and _start_time(marked[0]) == marked[1]:
                found.bringups.append(marked[0])
            else:
                found.left.append(pid)
        elif _bringup_of(argv, package) == (host, namespace):
            found.bringups.append(pid)
        else:
            for fqn in running_nodes(argv):
                found.nodes.setdefault(fqn, pid)
    found.bringups = sorted(set(found.bringups))
    return found


def running_nodes(argv: Sequence[str]) -> List[str]:
    """
    Return the fully qualified names of the nodes a command line names.

    A ``__ns`` remapping belongs to the ``__node`` remapping just before or
    after it (a component container names several nodes in turn); without
    one, the node of a package's executable (``.../lib/<package>/<name>``)
    is named as the executable, as a generated component's is; a shared
    Python process of a system names the instances of its description.
    """
    if 'robmosys_runtime.hosting.container' in argv:
        return _shared_nodes(list(argv))
    nodes: List[List[Optional[str]]] = []
    pending: Optional[str] = None
    last_was_node = False
    words = iter(argv)
    for word in words:
        if word not in ('-r', '--remap'):
            continue
        target, sep, value = next(words, '').partition(':=')
        # a rule of one node (name:__node:=x) renames it all the same
        what = target.rsplit(':', 1)[-1] if sep else ''
        if what == '__node':
            nodes.append([value, pending])
            pending = None
        elif what == '__ns' and last_was_node and nodes[-1][1] is None:
            nodes[-1][1] = value
        elif what == '__ns':
            pending = value
        last_was_node = what == '__node'
    if not nodes:
        # ros2 run <package> <executable>: a generated component's node is
        # named as its executable (a script runs as 'python3 <script>')
        program = next((w for w in argv[:2] if os.path.basename(
            os.path.dirname(os.path.dirname(w))) == 'lib'), '')
        if program and os.path.basename(program) != 'bringup':
            nodes.append([os.path.basename(program), pending])
            pending = None
    if pending is not None and len(nodes) == 1 and nodes[0][1] is None:
        nodes[0][1] = pending
    return [_fqn(namespace, name) for name, namespace in nodes if name]


def wait_gone(pids: Sequence[int], timeout: float,
              stopped: Callable[[], bool] = lambda: False) -> List[int]:
    """Wait for processes to end within timeout (or until stopped); kill and return the rest."""
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline and not stopped():
        if not [p for p in pids if _alive(p)]:
            return []
        time.sleep(0.05)
    killed = []
    for pid in pids:
        if _alive(pid):
            try:
                os.kill(pid, signal.SIGKILL)
                killed.append(pid)
            except ProcessLookupError:
                pass
    deadline = time.monotonic() + 2.0
    while [p for p in pids if _alive(p)] and time.monotonic() < deadline:
        time.sleep(0.05)
    return killed


def _shared_nodes(argv: List[str]) -> List[str]:
    """Return the nodes of a shared process of a system: its instances, in its description."""
    args = shared_arguments(argv[argv.index('robmosys_runtime.hosting.container') + 1:])
    if args is None:
        return []
    try:
        with open(args.description_file, encoding='utf-8') as stream:
            instances = json.load(stream)['instances']
    except (OSError, ValueError, KeyError, TypeError):
        return []
    return [i['fqn'] for i in instances if i.get('instance') in args.names and 'fqn' in i]


def _bringup_of(argv: Sequence[str], package: str) -> Optional[tuple]:
    """
    Return (host, namespace) of a command line that runs the bringup of a package.

    None if it is no such command line, or it is a ``--check`` (it starts nothing).
    """
    if not any(w.endswith(f'/lib/{package}/bringup') for w in argv[:2]):
        return None
    options: Dict[str, str] = {}
    words = iter(argv[2:])
    for word in words:
        if word == '--ros-args':
            break
        name, sep, value = word.partition('=')
        if name in ('--host', '--namespace'):
            options[name] = value if sep else next(words, '')
        elif word == '--check':
            return None
    where = options.get('--namespace', '').strip().strip('/')
    return options.get('--host', ''), f'/{where}' if where else ''


def _fqn(namespace: Optional[str], name: str) -> str:
    where = (namespace or '').strip('/')
    return f'/{where}/{name}' if where else f'/{name}'


def _marked(value: str) -> Optional[List[Any]]:
    if not value:
        return None
    try:
        marked = json.loads(value)
    except ValueError:
        return None
    if not isinstance(marked, list) or len(marked) != 5 or not isinstance(marked[0], int):
        return None
    return marked


def _read(pid: Any, name: str) -> Optional[bytes]:
    try:
        with open(f'/proc/{pid}/{name}', 'rb') as stream:
            return stream.read()
    except OSError:
        return None


def _environ(pid: int) -> Optional[Dict[str, str]]:
    text = _read(pid, 'environ')
    if text is None:
        return None
    pairs = (item.decode('utf-8', 'replace').partition('=') for item in text.split(b'\0'))
    return {name: value for name, sep, value in pairs if sep}


def _argv(pid: int) -> List[str]:
    text = _read(pid, 'cmdline') or b''
    return [word.decode('utf-8', 'replace') for word in text.split(b'\0')[:-1]]


def _domain(environ: Any) -> str:
    return environ.get('ROS_DOMAIN_ID', '').strip() or '0'


def _net(pid: Any) -> Optional[int]:
    try:
        return os.stat(f'/proc/{pid}/ns/net').st_ino
    except OSError:
        return None


def _start_time(pid: int) -> Optional[str]:
    """Return when a process started (clock ticks after boot), None if it does not run."""
    text = _read(pid, 'stat')
    if text is None:
        return None
    # the name, in parentheses, may hold spaces: the fields follow its end
    fields = text[text.rindex(b')') + 2:].split()
    # field 22 of proc(5), the 20th after the name
    return fields[19].decode() if len(fields) > 19 else None


def _alive(pid: int) -> bool:
    text = _read(pid, 'stat')
    # a zombie has ended: its parent has not read its status yet
    return text is not None and text[text.rindex(b')') + 2:].split()[:1] != [b'Z']


def _ancestors() -> Set[int]:
    """Return this process and those that started it: none of them is another bringup."""
    found: Set[int] = set()
    pid = os.getpid()
    while pid > 0 and pid not in found:
        found.add(pid)
        status = _read(pid, 'status') or b''
        parents = [line.split()[1] for line in status.splitlines() if line.startswith(b'PPid:')]
        pid = int(parents[0]) if parents else 0
    return found
