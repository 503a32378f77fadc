# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

"""Systems become packages of launch files, parameters and a diagram."""

from __future__ import annotations

from pathlib import Path
from typing import Any, Sequence

from colcon_robmosys.model.build import freeze_parameter_value
from colcon_robmosys.model.names import connection_name, node_name
from colcon_robmosys.model.types import (
    Component, Connection, Instance, Pattern, PortRef, Role, System,
    Workspace)
from colcon_robmosys.ros2.common import banner_context, package_xml_context
from colcon_robmosys.ros2.plan import FileSpec, PackagePlan

PARAMS_FILE = 'cfg/params.yaml'

#: The patterns whose data goes from the required port to the provided one.
_TO_PROVIDER = (Pattern.SEND, Pattern.QUERY, Pattern.ACTION)


def node_fqn(instance: Instance) -> str:
    """Return the fully qualified node name of an instance."""
    return node_name(instance.namespace, instance.name)


def provided_end(connection: Connection, components: dict[str, Component]
                 ) -> PortRef:
    """Return the end of a valid connection whose port is provided."""
    for end in (connection.source, connection.target):
        port = components[end.instance].port(end.port)
        assert port is not None
        if port.role is Role.PROVIDED:
            return end
    raise AssertionError(f'no provided end in {connection}')


def connection_topics(system: System, components: dict[str, Component]
                      ) -> dict[tuple[str, str], str]:
    """Return the ROS 2 name every connected port is remapped to.

    The provided end names a connection (see
    :func:`colcon_robmosys.model.names.connection_name`): the publisher of
    a push port, the server of a send, query, action or event port. The
    validation made sure a port takes one name only.
    """
    topics: dict[tuple[str, str], str] = {}
    for connection in system.connections:
        provided = provided_end(connection, components)
        instance = system.instance(provided.instance)
        assert instance is not None
        topic = connection_name(instance.namespace, provided.instance,
                                provided.port, connection.topic)
        for end in (connection.source, connection.target):
            topics[(end.instance, end.port)] = topic
    return topics


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
          topics: dict[tuple[str, str], str]) -> dict[str, Any]:
    remappings = [(p.name, topics[(instance.name, p.name)])
                  for p in component.ports
                  if (instance.name, p.name) in topics]
    return {
        'instance': instance.name,
        'package': component.package,
        'executable': component.name,
        'name': instance.name,
        'namespace': instance.namespace,
        'remappings': remappings,
        'activate': instance.activate,
        'after': list(instance.after),
        'fqn': node_fqn(instance),
    }


def _launch_files(system: System, nodes: list[dict[str, Any]],
                  banner: dict[str, Any]) -> list[FileSpec]:
    files = []
    variants: list[tuple[str, Sequence[dict[str, Any]], str]] = [
        ('', nodes, f'every instance of the system {system.name}')]
    variants += [(f'.{n["instance"]}', [n], f'the instance {n["instance"]} '
                  f'of the system {system.name}') for n in nodes]
    for suffix, selected, what in variants:
        # a file waits only for instances it activates itself: an instance
        # started by another file, or left unmanaged, would never be seen
        managed = {n['instance'] for n in selected if n['activate']}
        selected = [dict(n, activate_after=[a for a in n['after'] if a in managed])
                    for n in selected]
        context = {
            'banner': banner, 'package': system.package,
            'params_file': PARAMS_FILE, 'nodes': selected,
            'what': what,
        }
        files.append(FileSpec(f'launch/launch{suffix}.py',
                              'system/launch.py.jinja', context))
        files.append(FileSpec(f'launch/activate{suffix}.py',
                              'system/activate.py.jinja', context))
    return files


def _parameters(system: System, components: dict[str, Component]
                ) -> list[dict[str, Any]]:
    nodes = []
    for instance in system.instances:
        if not instance.parameters:
            continue
        types = {p.name: p.type for p in components[instance.name].parameters}
        # ROS 2 refuses an integer for a parameter declared as double
        values = [(name, freeze_parameter_value(types[name], value))
                  for name, value in instance.parameters]
        nodes.append({'fqn': node_fqn(instance), 'values': values})
    return nodes


def _diagram(system: System, components: dict[str, Component],
             topics: dict[tuple[str, str], str]) -> dict[str, Any]:
    instances = []
    for instance in system.instances:
        component = components[instance.name]
        instances.append({
            'name': instance.name, 'fqn': node_fqn(instance),
            'component': component.name, 'package': component.package,
            'managed': instance.activate,
            'ports': [{'name': p.name, 'role': p.role.value,
                       'pattern': p.pattern.value} for p in component.ports],
        })
    edges = []
    for connection in system.connections:
        source = provided_end(connection, components)
        target = (connection.target if source == connection.source
                  else connection.source)
        port = components[source.instance].port(source.port)
        assert port is not None
        # arrows follow the data: from the publisher of push and event, to
        # the server of send, query and action
        if port.pattern in _TO_PROVIDER:
            source, target = target, source
        edges.append({
            'source': source.instance, 'source_port': source.port,
            'target': target.instance, 'target_port': target.port,
            'label': f'{port.pattern.value} {port.type}\\n'
                     f'{topics[(source.instance, source.port)]}',
        })
    return {'name': system.name, 'instances': instances, 'edges': edges}


def plan_system(system: System, workspace: Workspace) -> PackagePlan:
    """Map a system to its package plan (the model is valid)."""
    components: dict[str, Component] = {}
    for instance in system.instances:
        component = workspace.model(instance.component)
        assert isinstance(component, Component)
        components[instance.name] = component
    topics = connection_topics(system, components)
    banner = banner_context(system)
    order = activation_order(system)
    nodes = [_node(i, components[i.name], topics) for i in order]
    packages = list(dict.fromkeys(c.package for c in components.values()))
    exec_depends = packages + ['launch', 'launch_ros', 'lifecycle_msgs',
                               'ament_index_python']
    files = _launch_files(system, nodes, banner)
    diagram = f'doc/{system.package}.dot'
    files += [
        FileSpec(PARAMS_FILE, 'system/params.yaml.jinja',
                 {'banner': banner,
                  'nodes': _parameters(system, components)}),
        FileSpec(diagram, 'system/diagram.dot.jinja',
                 {'banner': banner,
                  **_diagram(system, components, topics)}),
        FileSpec('CMakeLists.txt', 'system/CMakeLists.txt.jinja',
                 {'banner': banner, 'package': system.package,
                  'diagram': diagram}),
        FileSpec('package.xml', 'common/package.xml.jinja', {
            'banner': banner,
            **package_xml_context(system.info, buildtool=['ament_cmake'],
                                  exec_=exec_depends)}),
    ]
    return PackagePlan(
        name=system.package, kind='system',
        model_dir=Path(system.info.model_file).parent,
        build_depends=tuple(packages), exec_depends=tuple(exec_depends),
        files=tuple(files), summary={'nodes': nodes})
