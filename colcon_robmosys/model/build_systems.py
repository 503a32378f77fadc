# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

"""Build the systems of a file: instances, subsystems, connections."""

from __future__ import annotations

from dataclasses import replace
from typing import Any

from colcon_robmosys.errors import Location
from colcon_robmosys.model.build_base import BuilderBase
from colcon_robmosys.model.loader import NodePath, RawData
from colcon_robmosys.model.types import (
    Connection, Executor, Instance, Mode, ModeValues, PortRef, QoSOverride, Subsystem,
    System)


class SystemBuilder(BuilderBase):
    """Systems, with the rules a single system has to follow."""

    def system(self, path: NodePath, raw: RawData, defaults: RawData) -> System:
        """Build the system at the path of the file."""
        info = self._info(path, raw, defaults, 'system')
        name = raw.get('name') or _camel(info.name)
        if 'name' in raw:
            self.check_name(path + ('name',), 'system', name, key=False)
        instances = []
        for iname, body in raw.get('instances', {}).items():
            ipath = path + ('instances', iname)
            self.check_name(ipath, 'instance', iname)
            namespace = body.get('namespace', '')
            if namespace and not namespace.startswith('/'):
                namespace = '/' + namespace
            parameters = tuple(body.get('parameters', {}).items())
            instances.append(Instance(
                iname, body['component'], namespace.rstrip('/'), parameters,
                body.get('activate', True), tuple(body.get('after', ())),
                body.get('description', ''), self.at(ipath, key=True),
                tuple(self.at(ipath + ('parameters', n), key=True)
                      for n, _ in parameters),
                bool(body.get('respawn', False)), body.get('timeout'),
                body.get('host', ''), qos=self._qos_overrides(ipath, body),
                after_locations=self.at_each(ipath + ('after',), body.get('after', ())),
                parameter_entry_locations=self._entries(ipath + ('parameters',), parameters),
                unconnected=tuple(body.get('unconnected', ())),
                quiet=tuple(body.get('quiet', ())),
                watch_locations=(
                    self.at_each(ipath + ('unconnected',), body.get('unconnected', ())) +
                    self.at_each(ipath + ('quiet',), body.get('quiet', ())))))
        # a subsystem's host has launch files too
        hosts = {i.host for i in instances if i.host} | {
            body['host'] for body in raw.get('subsystems', {}).values() if body.get('host')}
        for instance in instances:
            if instance.name.startswith('on_') and instance.name[3:] in hosts:
                # <system>.on_<host>.launch.py starts the instances of a host
                self.error(path + ('instances', instance.name),
                           f"instance name '{instance.name}' is the name of the launch "
                           f"files of the host '{instance.name[3:]}'", key=True)
        subsystems = []
        for sname, body in raw.get('subsystems', {}).items():
            spath = path + ('subsystems', sname)
            self.check_name(spath, 'subsystem', sname)
            if sname in raw.get('instances', {}):
                self.error(spath, f"subsystem '{sname}' has the name of an instance",
                           key=True)
            namespace = body.get('namespace', sname)
            subsystems.append(Subsystem(
                sname, body['system'], '/' + namespace.strip('/') if namespace.strip('/')
                else '', self.at(spath, key=True), body.get('host', '')))
        if not raw.get('instances') and not subsystems:
            self.error(path, "a system has 'instances' or 'subsystems'", key=True)
        connections = []
        for index, body in enumerate(raw.get('connections', [])):
            cpath = path + ('connections', index)

            def ref(end: str) -> PortRef:
                # subsystem.instance.port: the instance is subsystem.instance
                instance, port = body[end].rsplit('.', 1)
                return PortRef(instance, port, self.at(cpath + (end,)))

            ends = [end for end in ('from', 'to') if end in body]
            if not ends or (len(ends) == 1 and 'topic' not in body):
                self.error(cpath, "a connection joins 'from' and 'to', or one port and "
                           "a 'topic' (a ROS 2 name outside the model)", key=True)
                continue
            connections.append(Connection(ref(ends[0]), ref(ends[-1]) if len(ends) == 2
                                          else None, body.get('topic'),
                                          self.at(cpath, key=True)))
        everywhere = tuple(raw.get('parameters', {}).items())
        modes = raw.get('modes', {})
        system = System(
            info, name, tuple(instances), tuple(connections), self.at(path + ('package',)),
            raw.get('processes', ''), tuple(subsystems), everywhere,
            tuple(self.at(path + ('parameters', n), key=True) for n, _ in everywhere),
            self._entries(path + ('parameters',), everywhere),
            Executor(raw['executor']) if 'executor' in raw else None,
            self.at(path + ('executor',)) if 'executor' in raw else None)
        if not modes:
            return system
        return replace(system, modes=self._modes(path + ('modes',), modes),
                       initial_mode=modes['initial'],
                       initial_mode_location=self.at(path + ('modes', 'initial')))

    def _modes(self, path: NodePath, raw: RawData) -> tuple[Mode, ...]:
        """Return the modes of a system (``modes: {initial: name, name: mode}``)."""
        modes = []
        for name, body in raw.items():
            if name == 'initial':
                continue
            mpath = path + (name,)
            active = tuple(body.get('active', ()))
            values = []
            for instance, given in body.get('parameters', {}).items():
                ipath = mpath + ('parameters', instance)
                pairs = tuple(given.items())
                values.append(ModeValues(
                    instance, pairs, self.at(ipath, key=True),
                    tuple(self.at(ipath + (n,), key=True) for n, _ in pairs),
                    self._entries(ipath, pairs)))
            subsystems = tuple(body.get('subsystems', {}).items())
            modes.append(Mode(
                name, active, tuple(values), subsystems, self.at(mpath, key=True),
                self.at_each(mpath + ('active',), active),
                tuple(self.at(mpath + ('subsystems', s)) for s, _ in subsystems),
                body.get('description', '')))
        return tuple(modes)

    def _entries(self, path: NodePath, values: tuple[tuple[str, Any], ...]
                 ) -> tuple[tuple[Location, ...], ...]:
        """Return where each element of each list value stands (none for a scalar)."""
        return tuple(self.at_each(path + (name,), value) if isinstance(value, list) else ()
                     for name, value in values)

    def _qos_overrides(self, path: NodePath, raw: RawData) -> tuple[QoSOverride, ...]:
        """Return the QoS an instance gives its ports (``qos: {port: {policy: value}}``)."""
        overrides = []
        for port, policies in raw.get('qos', {}).items():
            if policies.get('history') == 'keep_all' and 'depth' in policies:
                self.error(path + ('qos', port, 'depth'), f"instance '{path[-1]}', port "
                           f"'{port}': 'depth' has no meaning with history 'keep_all'")
            overrides.append(QoSOverride(port, tuple(policies.items()),
                                         self.at(path + ('qos', port), key=True)))
        return tuple(overrides)


def _camel(package: str) -> str:
    return ''.join(part.capitalize() for part in package.split('_'))
