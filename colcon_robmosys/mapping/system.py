# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

"""Systems become packages of launch files, parameters and a diagram."""

from __future__ import annotations

from dataclasses import dataclass, replace
import json
from typing import Any

from colcon_robmosys.mapping.common import (
    Banner, banner_of, package_xml, PackageXml, unique)
from colcon_robmosys.mapping.component import plan_component
from colcon_robmosys.mapping.connections import (
    connection_topics, node_fqn, provided_end, system_connections, SystemConnection)
from colcon_robmosys.mapping.cpp import RUNTIME_PACKAGE
from colcon_robmosys.mapping.portkinds import port_kind
from colcon_robmosys.model.parameters import freeze_parameter_value
from colcon_robmosys.model.types import Component, Instance, Language, System, Workspace

PARAMS_FILE = 'cfg/params.yaml'


@dataclass(frozen=True)
class SystemNode:
    """An instance as a lifecycle node of the launch files."""

    instance: str
    package: str
    executable: str
    name: str
    namespace: str
    #: (port, ROS 2 name) for each connected port
    remappings: tuple[tuple[str, str], ...]
    activate: bool
    after: tuple[str, ...]
    fqn: str
    #: the instances of the same launch file it waits for
    activate_after: tuple[str, ...] = ()
    #: started again when its process ends
    respawn: bool = False
    #: seconds for each lifecycle transition; None: the bring-up's default
    timeout: float | None = None
    #: the host it runs on; '' for the manager's
    host: str = ''
    #: module:class of a Python component (``bringup`` runs shared processes with it)
    python_class: str = ''
    #: the rclcpp_components plugin of a C++ component (its shared container loads it)
    plugin: str = ''


@dataclass(frozen=True)
class LaunchAlias:
    """A launch file under its name of the last release, including its new one."""

    banner: Banner
    package: str
    old: str
    new: str


@dataclass(frozen=True)
class LaunchFile:
    """A launch file, and its activate twin: all instances or one.

    Named as ROS 2 names launch files, ``<name>.launch.py``: the system's
    ``<system>.launch.py`` starts and activates every instance,
    ``<system>.nodes.launch.py`` only starts them; each instance has
    ``<system>.<instance>.launch.py`` and ``<system>.<instance>.nodes.launch.py``
    (an instance may not be called ``nodes``). The names of the last release,
    ``launch{suffix}.py`` and ``activate{suffix}.py``, stay as aliases.
    """

    suffix: str
    banner: Banner
    package: str
    params_file: str
    nodes: tuple[SystemNode, ...]
    what: str
    #: instances it activates that the launch file of their host starts
    remote: tuple[SystemNode, ...] = ()

    @property
    def stem(self) -> str:
        """Return the name the launch files share: the system's, or with an instance."""
        return f'{self.package}{self.suffix}'

    @property
    def activate_file(self) -> str:
        """Return the file name of the launch file that also activates."""
        return f'{self.stem}.launch.py'

    @property
    def nodes_file(self) -> str:
        """Return the file name of the launch file that only starts the nodes."""
        return f'{self.stem}.nodes.launch.py'

    @property
    def has_manager(self) -> bool:
        """Tell whether the file starts the system manager: the system's own file does."""
        return self.suffix == ''

    @property
    def activates_itself(self) -> bool:
        """Tell whether the file activates its instances itself (one instance, a host)."""
        return not self.has_manager

    @property
    def has_aliases(self) -> bool:
        """Tell whether the last release had the file: the files of hosts are new."""
        return not self.suffix.startswith('.on_')

    @property
    def activate_alias(self) -> LaunchAlias:
        """Return the alias of the activating file under its former name."""
        return LaunchAlias(self.banner, self.package, f'activate{self.suffix}.py',
                           self.activate_file)

    @property
    def nodes_alias(self) -> LaunchAlias:
        """Return the alias of the starting file under its former name."""
        return LaunchAlias(self.banner, self.package, f'launch{self.suffix}.py',
                           self.nodes_file)


@dataclass(frozen=True)
class NodeParameters:
    """The parameter overrides of one node, in cfg/params.yaml."""

    fqn: str
    values: tuple[tuple[str, Any], ...]


@dataclass(frozen=True)
class DiagramPort:
    """A port in the diagram."""

    name: str
    role: str
    pattern: str


@dataclass(frozen=True)
class DiagramInstance:
    """An instance in the diagram."""

    name: str
    fqn: str
    component: str
    package: str
    managed: bool
    ports: tuple[DiagramPort, ...]


@dataclass(frozen=True)
class DiagramEdge:
    """A connection in the diagram, drawn the way the data flows."""

    source: str
    source_port: str
    target: str
    target_port: str
    label: str


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
    #: 'per_instance', or 'shared': bringup runs the Python instances of a host in one process
    processes: str = 'per_instance'

    @property
    def bringup_description(self) -> str:
        """Return what ``ros2 run <system> bringup`` reads: the instances, as JSON.

        robmosys_runtime.bringup starts them as the launch files do and brings
        the managed ones up in order.
        """
        instances = [{
            'instance': n.instance, 'package': n.package, 'executable': n.executable,
            'name': n.name, 'namespace': n.namespace, 'fqn': n.fqn,
            'remappings': [list(r) for r in n.remappings], 'managed': n.activate,
            'after': list(n.after), 'respawn': n.respawn, 'timeout': n.timeout,
            'host': n.host, 'python_class': n.python_class, 'plugin': n.plugin}
            for n in self.nodes]
        connections = [{'name': c.name, 'entity': c.entity, 'type': c.type,
                        'from': c.source, 'to': c.target} for c in self.connections]
        return json.dumps({'generated_by': ' '.join(self.banner.lines),
                           'package': self.package, 'params_file': PARAMS_FILE,
                           'processes': self.processes,
                           'instances': instances, 'connections': connections},
                          indent=2, sort_keys=True) + '\n'


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
    return SystemNode(
        instance=instance.name, package=component.package,
        executable=component.name, name=instance.name,
        namespace=instance.namespace,
        remappings=tuple((p.name, topics[(instance.name, p.name)])
                         for p in component.ports
                         if (instance.name, p.name) in topics),
        activate=instance.activate, after=instance.after,
        fqn=node_fqn(instance), respawn=instance.respawn, timeout=instance.timeout,
        host=instance.host,
        **_in_process(component))


def _in_process(component: Component) -> dict[str, str]:
    """Return how a process of several instances creates the node of a component.

    Python: module:class of the node its executable runs; C++: the
    rclcpp_components plugin its package registers (component.cpp.jinja).
    """
    plan = plan_component(component)
    if component.language is Language.PYTHON:
        return {'python_class': f'{plan.package}.{plan.node_module}:{plan.node_cls}'}
    return {'plugin': f'{plan.package}::{plan.node_cls}'}


def _launch_files(system: System, nodes: tuple[SystemNode, ...],
                  banner: Banner) -> tuple[LaunchFile, ...]:
    local = tuple(n for n in nodes if not n.host)
    remote = tuple(n for n in nodes if n.host)
    # the system's files start the instances of the manager's host, and
    # activate those of every host
    variants = [('', local, remote, f'every instance of the system {system.name}'
                 + (' that runs on no host of its own' if remote else ''))]
    variants += [(f'.{n.instance}', (n,), (), f'the instance {n.instance} '
                  f'of the system {system.name}') for n in nodes]
    variants += [(f'.on_{host}', tuple(n for n in remote if n.host == host), (),
                  f'the instances of the system {system.name} on the host {host}')
                 for host in unique(n.host for n in remote)]
    files = []
    for suffix, selected, elsewhere, what in variants:
        # a file waits only for instances it activates itself: an instance
        # started by another file, or left unmanaged, would never be seen
        managed = {n.instance for n in selected + elsewhere if n.activate}

        def waiting(chosen: tuple[SystemNode, ...]) -> tuple[SystemNode, ...]:
            return tuple(replace(n, activate_after=tuple(a for a in n.after if a in managed))
                         for n in chosen)
        files.append(LaunchFile(suffix, banner, system.package, PARAMS_FILE,
                                waiting(selected), what, waiting(elsewhere)))
    return tuple(files)


def _parameters(system: System, components: dict[str, Component]
                ) -> tuple[NodeParameters, ...]:
    nodes = []
    for instance in system.instances:
        if not instance.parameters:
            continue
        types = {p.name: p.type for p in components[instance.name].parameters}
        # ROS 2 refuses an integer for a parameter declared as double
        nodes.append(NodeParameters(node_fqn(instance), tuple(
            (name, freeze_parameter_value(types[name], value))
            for name, value in instance.parameters)))
    return tuple(nodes)


def _instances(system: System, components: dict[str, Component]
               ) -> tuple[DiagramInstance, ...]:
    return tuple(
        DiagramInstance(
            name=i.name, fqn=node_fqn(i), component=components[i.name].name,
            package=components[i.name].package, managed=i.activate,
            ports=tuple(DiagramPort(p.name, p.role.value, p.pattern.value)
                        for p in components[i.name].ports))
        for i in system.instances)


def _edges(system: System, components: dict[str, Component],
           topics: dict[tuple[str, str], str]) -> tuple[DiagramEdge, ...]:
    edges = []
    for connection in system.connections:
        source = provided_end(connection, components)
        target = (connection.target if source == connection.source
                  else connection.source)
        port = components[source.instance].port(source.port)
        assert port is not None
        # arrows follow the data: from the publisher of push and event, to
        # the server of send, query and action
        if port_kind(port).data_to_provider:
            source, target = target, source
        edges.append(DiagramEdge(
            source.instance, source.port, target.instance, target.port,
            f'{port.pattern.value} {port.type}\\n'
            f'{topics[(source.instance, source.port)]}'))
    return tuple(edges)


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
    return SystemPackage(
        banner=banner, package=system.package, name=system.name, nodes=nodes,
        launch_files=_launch_files(system, nodes, banner),
        params=_parameters(system, components),
        diagram=f'doc/{system.package}.dot',
        instances=_instances(system, components),
        edges=_edges(system, components, topics),
        connections=system_connections(system, components, topics),
        processes=system.processes,
        depends=packages, exec_depends=exec_depends,
        package_xml=package_xml(banner, system.info, buildtool=['ament_cmake'],
                                exec_=exec_depends,
                                test=('ament_cmake_pytest', 'ament_cmake_ros')))
