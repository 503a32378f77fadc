# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

"""Systems become packages of launch files, parameters and a diagram."""

from __future__ import annotations

from dataclasses import dataclass
import json
from typing import Any, Iterable

from colcon_robmosys.mapping.backends import DEFAULT_EXECUTORS, node_start
from colcon_robmosys.mapping.common import (
    Banner, banner_of, INSTALLED_MODEL, package_xml, PackageXml,
    RUNTIME_PACKAGE, unique)
from colcon_robmosys.mapping.conformance import watched_instances, WatchedInstance
from colcon_robmosys.mapping.connections import (
    connection_topics, node_fqn, system_connections, SystemConnection)
from colcon_robmosys.mapping.declared import declared_parameters, DeclaredParameter
from colcon_robmosys.mapping.diagram import (
    diagram_edges, diagram_instances, DiagramEdge, DiagramInstance)
from colcon_robmosys.mapping.executors import shared_executors
from colcon_robmosys.mapping.launch import (
    launch_files, LaunchFile, PARAMS_FILE, process_layout, SystemNode)
from colcon_robmosys.mapping.layout import lay_out, Layout
from colcon_robmosys.mapping.modes import ModePlan, plan_modes
from colcon_robmosys.mapping.names import connection_name
from colcon_robmosys.mapping.parameters import NODE_PARAMETERS
from colcon_robmosys.mapping.portkinds import port_kind
from colcon_robmosys.mapping.qos import override_parameters
from colcon_robmosys.model.parameters import freeze_parameter_value, node_parameters
from colcon_robmosys.model.types import Component, Instance, System, Workspace


@dataclass(frozen=True)
class NodeParameters:
    """The parameter overrides of one node, in cfg/params.yaml."""

    fqn: str
    values: tuple[tuple[str, Any], ...]


@dataclass(frozen=True)
class SystemPackage:
    """The plan of a system package."""

    banner: Banner
    package: str
    name: str
    #: in activation order
    nodes: tuple[SystemNode, ...]
    launch_files: tuple[LaunchFile, ...]
    #: the parameter file's nodes
    params: tuple[NodeParameters, ...]
    diagram: str
    instances: tuple[DiagramInstance, ...]
    edges: tuple[DiagramEdge, ...]
    depends: tuple[str, ...]
    exec_depends: tuple[str, ...]
    package_xml: PackageXml
    connections: tuple[SystemConnection, ...] = ()
    #: 'per_instance', or 'shared': the Python instances of a host in one process, the C++
    #: ones of the manager's host in a component container (bringup and the launch files)
    processes: str = 'per_instance'
    #: per instance, in model order: what the system manager's watch compares
    watched: tuple[WatchedInstance, ...] = ()
    #: whether it builds a component container for its C++ instances (any shares it
    #: with processes: shared, or bringup --shared)
    cpp_container: bool = False
    #: each model file of the workspace -> its installed copy (share/<package>/...), where
    #: bringup.json's locations point: they hold no path of the machine that built them
    model_files: tuple[tuple[str, str], ...] = ()
    #: per instance: the parameters its node declares (what a parameter file may set)
    declared: tuple[tuple[str, tuple[DeclaredParameter, ...]], ...] = ()
    #: language -> the executor of its shared process (mapping/executors.py)
    executors: tuple[tuple[str, str], ...] = ()
    #: its modes, whole (mapping/modes.py), and the one it starts in
    modes: tuple[ModePlan, ...] = ()
    initial_mode: str = ''
    #: the drawing of the system (doc/<package>.svg), which the manager's page shows too
    layout: Layout | None = None

    @property
    def has_modes(self) -> bool:
        """Tell whether the system has modes (and a page of them, doc/modes.md)."""
        return bool(self.modes)

    @property
    def svg(self) -> str:
        """Return the path of the drawing, beside the DOT file."""
        return self.diagram.removesuffix('.dot') + '.svg'

    @property
    def bringup_description(self) -> str:
        """Return what ``ros2 run <system> bringup`` reads: the instances, as JSON.

        robmosys_runtime.system.bringup starts them as the launch files do and brings
        the managed ones up in order.
        """
        instances: list[dict[str, Any]] = [{
            'instance': n.instance, 'package': n.package, 'executable': n.executable,
            'name': n.name, 'namespace': n.namespace, 'fqn': n.fqn,
            'remappings': [list(r) for r in n.remappings], 'managed': n.activate,
            'after': list(n.after), 'respawn': n.respawn, 'timeout': n.timeout,
            'host': n.host, 'python_class': n.python_class, 'plugin': n.plugin,
            'lifecycle': n.lifecycle, 'threads': n.threads}
            for n in self.nodes]
        watched = {w.instance: w for w in self.watched}
        installed = dict(self.model_files)
        declared = dict(self.declared)
        for instance in instances:
            instance['declared'] = [d.as_json() for d in declared.get(instance['instance'], ())]
            watch = watched.get(instance['instance'])
            if watch is not None:
                instance['location'] = installed_location(watch.location, installed)
                instance['ports'] = [
                    {'port': p.port, 'entity': p.entity, 'name': p.name, 'type': p.type,
                     'required': p.required, 'connected': p.connected, 'period': p.period,
                     'unconnected': p.unconnected, 'quiet': p.quiet} for p in watch.ports]
                instance['parameters'] = [
                    {'name': n, 'value': v, 'location': installed_location(at, installed)}
                    for n, v, at in watch.parameters]
        connections = [{'name': c.name, 'entity': c.entity, 'type': c.type,
                        'from': c.source, 'to': c.target,
                        'location': installed_location(c.location, installed)}
                       for c in self.connections]
        description = {'generated_by': ' '.join(self.banner.lines),
                       'package': self.package, 'params_file': PARAMS_FILE,
                       'processes': self.processes, 'executors': dict(self.executors),
                       'instances': instances, 'connections': connections}
        if self.modes:
            description['initial_mode'] = self.initial_mode
            description['modes'] = [
                {**m.as_json(), 'location': installed_location(m.location, installed)}
                for m in self.modes]
        return json_lines(description)


def json_lines(description: dict[str, Any]) -> str:
    """Return a dict as JSON, its keys sorted, each element of a list on a line of its own.

    Readable, an instance per line, and written by json's C encoder:
    ``indent=`` takes its pure-Python one, six times slower (0.82 s against 0.14 s
    for the 100 systems of 1000 synthetic components, bench/generation_cli.py).
    """
    lines = []
    for key in sorted(description):
        value = description[key]
        if isinstance(value, list) and value:
            items = ',\n'.join(f'    {json.dumps(item, sort_keys=True)}' for item in value)
            lines.append(f'  {json.dumps(key)}: [\n{items}\n  ]')
        else:
            lines.append(f'  {json.dumps(key)}: {json.dumps(value, sort_keys=True)}')
    return '{\n' + ',\n'.join(lines) + '\n}\n'


def activation_order(system: System) -> list[Instance]:
    """Return the instances in an order that respects ``after``."""
    done: list[Instance] = []
    pending = list(system.instances)
    while pending:
        ready = [i for i in pending
                 if all(a in {d.name for d in done} for a in i.after)]
        if not ready:  # a cycle, reported by validation
            ready = pending[:1]
        done.append(ready[0])
        pending.remove(ready[0])
    return done


def _node(instance: Instance, component: Component,
          topics: dict[tuple[str, str], str]) -> SystemNode:
    # how a process of several instances creates the node: its language's way
    start = node_start(component)
    return SystemNode(
        instance=instance.name, package=component.package,
        executable=component.executable_name, name=instance.node_name,
        namespace=instance.namespace,
        remappings=_remappings(instance, component, topics),
        # a plain node cannot be configured nor activated: started only
        activate=instance.activate and component.lifecycle_node,
        lifecycle=component.lifecycle_node, after=instance.after,
        fqn=node_fqn(instance), respawn=instance.respawn, timeout=instance.timeout,
        host=instance.host,
        python_class=start.python_class, plugin=start.plugin, threads=start.threads)


#: the services and topics of an action, below its name
ACTION_PARTS = ('_action/send_goal', '_action/cancel_goal', '_action/get_result',
                '_action/feedback', '_action/status')


def _remappings(instance: Instance, component: Component,
                topics: dict[tuple[str, str], str]) -> tuple[tuple[str, str], ...]:
    """Return the remapping rules that give the connected ports their ROS 2 names.

    The name a node gives a port is the port's, or an external node's own. Jazzy
    remaps an action only through the services and topics it is made of (ros2/rcl
    #1170 came in Kilted, which then ignores those rules), so an action's parts get
    rules of their own, and the same launch files work on both.
    """
    rules = []
    for port in component.ports:
        target = topics.get((instance.name, port.name))
        if target is None:
            continue
        rules.append((port.node_name, target))
        if port_kind(port).uses_actions:
            rules += [(f'{port.node_name}/{part}', f'{target}/{part}')
                      for part in ACTION_PARTS]
    return tuple(rules)


def _parameters(system: System, components: dict[str, Component],
                topics: dict[tuple[str, str], str]) -> tuple[NodeParameters, ...]:
    nodes = []
    # by ROS 2 name: a mapped parameter once per entry of its array
    declared = {i.name: node_parameters(components[i.name].parameters, {
        **dict(system.parameters), **dict(i.parameters)}) for i in system.instances}
    if system.parameters:
        # '/**' first: rcl takes the entries of a node in the order of the
        # file, so a node's own values, later, win
        types = {n: p.type for d in declared.values() for n, p in d.items()}
        types.update(NODE_PARAMETERS)
        nodes.append(NodeParameters('/**', tuple(
            (name, freeze_parameter_value(types[name], value))
            for name, value in system.parameters)))
    for instance in system.instances:
        component = components[instance.name]
        types = dict(NODE_PARAMETERS)
        types.update((n, p.type) for n, p in declared[instance.name].items())
        # ROS 2 refuses an integer for a parameter declared as double
        values = [(name, freeze_parameter_value(types[name], value))
                  for name, value in instance.parameters]
        for override in instance.qos:
            port = component.port(override.port)
            assert port is not None
            # an unconnected port keeps its own name, in the node's namespace
            topic = topics.get((instance.name, port.name)) or \
                connection_name(instance.namespace, instance.node_name, port.name, port.name)
            values += override_parameters(topic, port_kind(port).entity.value, override)
        if values:
            nodes.append(NodeParameters(node_fqn(instance), tuple(values)))
    return tuple(nodes)


def _installed_models(workspace: Workspace, locations: Iterable[str]) -> dict[str, str]:
    """Return where the model files of some locations are installed, by a package made from each.

    The first package of a file by name installs the copy a location names
    (the workspace knows it of each file: each of a thousand systems looked
    through every model).
    """
    wanted = {parts[0] for parts in map(_split_location, locations) if parts}
    first = {path: workspace.first_package_of(path) for path in wanted}
    return {path: f'share/{package}/{INSTALLED_MODEL}'
            for path, package in first.items() if package is not None}


def _split_location(location: str) -> tuple[str, str, str] | None:
    """Return the path, line and column of a location, None if it is no ``path:line:column``."""
    parts = location.rsplit(':', 2)
    if len(parts) != 3 or not (parts[1].isdigit() and parts[2].isdigit()):
        return None
    return parts[0], parts[1], parts[2]


def installed_location(location: str, installed: dict[str, str]) -> str:
    """
    Return a location (``path:line:column``) in the installed copy of its model file.

    The copy is the model's text as it is: a line and column of the model file
    are those of the copy (the system manager names the model file itself where
    it is there, robmosys_runtime.tools.locations). A model of an underlay was
    read from its installed copy already. A location in no such file is
    returned as it is.
    """
    parts = _split_location(location)
    if parts is None:
        return location
    path, line, column = parts
    if path in installed:
        return f'{installed[path]}:{line}:{column}'
    if '/share/' in path:
        return f"{path[path.rindex('/share/') + 1:]}:{line}:{column}"
    return location


def plan_system(system: System, workspace: Workspace) -> SystemPackage:
    """Map a checked system to its package plan."""
    components: dict[str, Component] = {}
    for instance in system.instances:
        component = workspace.model(instance.component)
        assert isinstance(component, Component)
        components[instance.name] = component
    topics = connection_topics(system, components)
    banner = banner_of(system)
    nodes = tuple(_node(i, components[i.name], topics)
                  for i in activation_order(system))
    packages = unique(c.package for c in components.values())
    # robmosys_runtime: the launch files activate with its SystemActivation
    exec_depends = packages + ('launch', 'launch_ros', 'lifecycle_msgs',
                               'ament_index_python', RUNTIME_PACKAGE)
    # C++ instances: the package builds their component container, robmosys_runtime's
    cpp_container = any(n.plugin for n in nodes)
    watched = watched_instances(system, components, topics)
    connections = system_connections(system, components, topics)
    modes = plan_modes(system, workspace, components, (n.instance for n in nodes), watched)
    instances = diagram_instances(system, components)
    edges = diagram_edges(system, components, topics)
    return SystemPackage(
        banner=banner, package=system.package, name=system.name, nodes=nodes,
        launch_files=launch_files(system, nodes, banner),
        params=_parameters(system, components, topics),
        diagram=f'doc/{system.package}.dot',
        instances=instances, edges=edges,
        layout=lay_out(system, components, instances, edges),
        connections=connections,
        processes=process_layout(system),
        watched=watched,
        model_files=tuple(sorted(_installed_models(workspace, [
            *(w.location for w in watched), *(at for w in watched for _, _, at in w.parameters),
            *(c.location for c in connections), *(m.location for m in modes)]).items())),
        modes=modes, initial_mode=system.initial_mode,
        declared=tuple((i.name, declared_parameters(i, components[i.name], topics,
                                                    dict(system.parameters)))
                       for i in system.instances),
        executors=shared_executors(system.executor, components.values(), DEFAULT_EXECUTORS),
        depends=packages, exec_depends=exec_depends, cpp_container=cpp_container,
        package_xml=package_xml(banner, system.info, buildtool=['ament_cmake'],
                                depend=(RUNTIME_PACKAGE, 'rclcpp_components')
                                if cpp_container else (),
                                exec_=exec_depends,
                                test=('ament_cmake_pytest', 'ament_cmake_ros')))
