# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

"""The system's drawing, laid out once from the model: boxes, lines, where each goes.

One layout makes the SVG installed with a system package (``doc/<package>.svg``)
and the page the system manager serves, which draws that same file: the
picture before and after start is one. It is computed here, in plain Python,
so that it is the same on every machine and needs no program at build or run
time (Graphviz laid out the diagram before; it is often not installed).

Instances stand in columns by how far along the data's way they are (a
publisher left of its subscribers, a client left of its server), grouped in a
box per host (the manager's host first) and in it a box per subsystem (the
part of an instance's name before its last dot). A connection is a curve from
the port its data leaves to the port it reaches, labelled where it leaves with
its pattern and ROS 2 name (once per port: the connections of one port share
their name; the type is the curve's title); a name outside the model is a
plain label on the right.
"""

from __future__ import annotations

from dataclasses import dataclass

from colcon_robmosys.mapping.connections import provided_end
from colcon_robmosys.mapping.diagram import DiagramEdge, DiagramInstance
from colcon_robmosys.mapping.qos import resolve_qos
from colcon_robmosys.model.types import Component, System

#: sizes, in SVG units (pixels at 100 %)
BOX_WIDTH = 220
HEADER = 40
PORT_ROW = 18
COLUMN = 500
GAP = 24
PAD = 16
GROUP_TITLE = 22
EXTERNAL_WIDTH = 200
#: room left of the first column for a connection that comes back to it (a cycle)
BACK = 48


@dataclass(frozen=True)
class Box:
    """A rectangle of the drawing: a group (host, subsystem) or an instance."""

    x: int
    y: int
    w: int
    h: int


@dataclass(frozen=True)
class LaidPort:
    """A port of a laid-out instance: its row's middle, and which side lines leave from."""

    name: str
    role: str
    pattern: str
    y: int


@dataclass(frozen=True)
class LaidInstance:
    """An instance of the drawing."""

    name: str
    fqn: str
    component: str
    package: str
    managed: bool
    host: str
    box: Box
    ports: tuple[LaidPort, ...]


@dataclass(frozen=True)
class LaidGroup:
    """A host's box, or a subsystem's inside it."""

    kind: str
    label: str
    box: Box


@dataclass(frozen=True)
class LaidConnection:
    """A connection of the drawing, index as in the model (and in ``bringup.json``)."""

    index: int
    source: str
    target: str
    label: str
    name: str
    qos: str
    type: str  # noqa: A003 - the model's word
    #: the SVG path of its curve, and where its label stands
    path: str
    label_x: int
    label_y: int
    #: whether its label is drawn: the first connection of the port it leaves
    labelled: bool = True


@dataclass(frozen=True)
class Layout:
    """The whole drawing."""

    width: int
    height: int
    groups: tuple[LaidGroup, ...]
    instances: tuple[LaidInstance, ...]
    connections: tuple[LaidConnection, ...]
    #: names outside the model: (name, box)
    externals: tuple[tuple[str, Box], ...]


def _columns(instances: tuple[DiagramInstance, ...],
             edges: tuple[DiagramEdge, ...]) -> dict[str, int]:
    """Return each instance's column: the longest way of data that reaches it (cycles cut)."""
    names = [i.name for i in instances]
    into: dict[str, list[str]] = {n: [] for n in names}
    for edge in edges:
        if edge.source in into and edge.target in into and edge.source != edge.target:
            into[edge.target].append(edge.source)
    column: dict[str, int] = {}

    def depth(name: str, path: frozenset[str]) -> int:
        if name not in column:
            before = [depth(s, path | {name}) + 1 for s in into[name] if s not in path]
            column[name] = max(before, default=0)
        return column[name]

    for name in names:
        depth(name, frozenset())
    return column


def _qos_text(component: Component, port_name: str) -> str:
    port = component.port(port_name)
    if port is None:
        return ''
    qos = resolve_qos(port.qos)
    text = f'{qos.history} {qos.depth}, {qos.reliability}, {qos.durability}'
    return f'{port.qos.profile}: {text}'


def lay_out(system: System, components: dict[str, Component],
            instances: tuple[DiagramInstance, ...],
            edges: tuple[DiagramEdge, ...]) -> Layout:
    """Return the drawing of a system: its groups, instances and connections placed."""
    column = _columns(instances, edges)
    hosts = {i.name: i.host for i in system.instances}
    order: dict[str, dict[str, list[DiagramInstance]]] = {}
    for instance in sorted(instances, key=lambda i: hosts[i.name] != ''):
        subsystem = instance.name.rpartition('.')[0]
        order.setdefault(hosts[instance.name], {}).setdefault(subsystem, []).append(instance)
    # room for connections that come back to an earlier column, where there are any
    back = BACK if any(column.get(e.target, 1 << 30) <= column.get(e.source, -1)
                       for e in edges) else 0
    width = 4 * PAD + back + max(column.values(), default=0) * COLUMN + BOX_WIDTH
    # names outside the model stand left of the hosts where data comes from them,
    # right where it goes to them
    left = EXTERNAL_WIDTH + PAD if any(not e.source_port for e in edges) else 0
    groups: list[LaidGroup] = []
    laid: dict[str, LaidInstance] = {}
    y = PAD
    for host, subsystems in order.items():
        host_top = y
        host_index = len(groups)
        y += GROUP_TITLE + PAD
        for subsystem, members in subsystems.items():
            top = y
            if subsystem:
                y += GROUP_TITLE
            # a row holds one instance per column: the next one of a column goes below
            bottoms: dict[int, int] = {}
            row_top = y + PAD
            for instance in members:
                x = left + 2 * PAD + back + column[instance.name] * COLUMN
                at = bottoms.get(column[instance.name], row_top)
                height = HEADER + PORT_ROW * len(instance.ports) + 6
                ports = tuple(LaidPort(p.name, p.role, p.pattern,
                                       at + HEADER + PORT_ROW * k + PORT_ROW // 2)
                              for k, p in enumerate(instance.ports))
                laid[instance.name] = LaidInstance(
                    instance.name, instance.fqn, instance.component, instance.package,
                    instance.managed, host, Box(x, at, BOX_WIDTH, height), ports)
                bottoms[column[instance.name]] = at + height + GAP
            y = max(bottoms.values(), default=row_top) + PAD // 2
            if subsystem:
                groups.append(LaidGroup('subsystem', subsystem,
                                        Box(left + PAD + 4, top, width - 2 * PAD - 8,
                                            y - top)))
                y += PAD // 2
        groups.insert(host_index, LaidGroup(
            'host', f'host {host}' if host else "the manager's host",
            Box(left + PAD - 8, host_top, width - 2 * PAD + 16, y - host_top)))
        y += GAP
    connections = []
    labelled: set[tuple[str, str]] = set()
    externals: dict[str, Box] = {}
    #: the next place of a name outside the model: (x, y) on each side
    lanes = {True: [PAD, PAD + GROUP_TITLE], False: [left + width + PAD, PAD + GROUP_TITLE]}
    for index, (edge, connection) in enumerate(zip(edges, system.connections)):
        ends = []
        for end, port, leaving in ((edge.source, edge.source_port, True),
                                   (edge.target, edge.target_port, False)):
            if not port:
                if end not in externals:
                    lane = lanes[leaving]
                    externals[end] = Box(lane[0], lane[1], EXTERNAL_WIDTH, 24)
                    lane[1] += 40
                box = externals[end]
                ends.append((box.x + (box.w if leaving else 0), box.y + 12))
                continue
            placed = laid[end]
            row = next(p.y for p in placed.ports if p.name == port)
            ends.append((placed.box.x + (placed.box.w if leaving else 0), row))
        (x1, y1), (x2, y2) = ends
        # forwards: an S as wide as the gap; backwards (a cycle), out of the source's
        # side and into the target's, in the room left and right of the columns
        bend = max(60, (x2 - x1) // 2) if x2 > x1 else BACK + 16
        path = f'M{x1},{y1} C{x1 + bend},{y1} {x2 - bend},{y2} {x2},{y2}'
        provided = provided_end(connection, components)
        kind, _, name = edge.label.partition('\\n')
        pattern, _, type_name = kind.partition(' ')
        connections.append(LaidConnection(
            index, f'{edge.source}.{edge.source_port}' if edge.source_port else edge.source,
            f'{edge.target}.{edge.target_port}' if edge.target_port else edge.target,
            pattern, name, _qos_text(components[provided.instance], provided.port),
            type_name, path, x1 + 8, y1 - 4, (edge.source, edge.source_port) not in labelled))
        labelled.add((edge.source, edge.source_port))
    right = any(box.x > left for box in externals.values())
    total_width = left + width + PAD + (EXTERNAL_WIDTH + PAD if right else 0)
    height = max(y, lanes[True][1], lanes[False][1]) + PAD
    return Layout(total_width, height, tuple(groups), tuple(laid[i.name] for i in instances),
                  tuple(connections), tuple(externals.items()))
