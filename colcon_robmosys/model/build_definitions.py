# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

"""Build the service definitions of a file: structures, fields, constants."""

from __future__ import annotations

from dataclasses import replace
from functools import partial

from colcon_robmosys.model import names
from colcon_robmosys.model.build_base import BuilderBase
from colcon_robmosys.model.fieldtypes import (
    interface_comment_problem, parse_field_type, TypeNameError, value_problem)
from colcon_robmosys.model.loader import NodePath, RawData
from colcon_robmosys.model.types import (
    Action, CommunicationObject, Constant, Event, Field, FieldType, Query,
    ServiceDefinition, Structure)


class DefinitionBuilder(BuilderBase):
    """Service definitions: communication objects, queries, actions, events."""

    def service_definition(self, path: NodePath, raw: RawData,
                           defaults: RawData) -> ServiceDefinition:
        """Build the service definition at the path of the file."""
        info = self._info(path, raw, defaults, 'service definition')
        package = info.name
        seen: dict[str, str] = {}

        def named(section: str, name: str) -> None:
            problem = names.name_problem('interface', name, names.INTERFACE_SECTIONS[section])
            if problem:
                self.error(path + (section, name), problem, key=True)
            if name in seen:
                self.error(path + (section, name),
                           f"'{name}' is already defined in {seen[name]}",
                           key=True)
            seen[name] = section

        objects = []
        for name, body in raw.get('communication_objects', {}).items():
            named('communication_objects', name)
            objects.append(CommunicationObject(
                name, self._structure(
                    path + ('communication_objects', name), body, package),
                self.at(path + ('communication_objects', name), key=True)))
        queries = []
        for name, body in raw.get('queries', {}).items():
            named('queries', name)
            qpath = path + ('queries', name)
            self._comment(qpath + ('description',),
                          body.get('description', ''), f"the description of query '{name}'")
            queries.append(Query(
                name, body.get('description', ''),
                self._structure(qpath + ('request',),
                                body.get('request', {}), package),
                self._structure(qpath + ('answer',),
                                body.get('answer', {}), package),
                self.at(qpath, key=True)))
        actions = []
        for name, body in raw.get('actions', {}).items():
            named('actions', name)
            apath = path + ('actions', name)
            goal, result, feedback = (
                self._structure(apath + (part,), body.get(part, {}), package)
                for part in ('goal', 'result', 'feedback'))
            self._comment(apath + ('description',),
                          body.get('description', ''), f"the description of action '{name}'")
            actions.append(Action(
                name, body.get('description', ''), goal, result, feedback,
                self.at(apath, key=True)))
        events = []
        for name, body in raw.get('events', {}).items():
            named('events', name)
            epath = path + ('events', name)
            if 'single' in ((body.get('activation') or {}).get('fields') or
                            {}):
                self.error(epath + ('activation', 'fields', 'single'),
                           f"event '{name}': the activation field 'single' "
                           'is reserved: it carries the mode of an '
                           'activation (single or continuous)', key=True)
            self._comment(epath + ('description',),
                          body.get('description', ''), f"the description of event '{name}'")
            events.append(Event(
                name, body.get('description', ''),
                self._structure(epath + ('activation',),
                                body.get('activation', {}), package),
                self._structure(epath + ('event',), body.get('event', {}),
                                package),
                self.at(epath, key=True)))
        if not (objects or queries or actions or events):
            self.error(path, f"service definition '{package}' defines no "
                       'communication object, query, action or event')
        external = bool(raw.get('external', False))
        if external and events:
            self.error(path + ('events',), 'an installed package holds actions, not events: '
                       "describe its actions under 'actions'", key=True)
        return ServiceDefinition(info, tuple(objects), tuple(queries),
                                 tuple(actions), tuple(events), external)

    def _field_type(self, path: NodePath, text: str, package: str,
                    what: str) -> FieldType | None:
        try:
            return parse_field_type(text, package)
        except TypeNameError as exc:
            self.error(path, f'{what}: {exc}')
            return None

    def _structure(self, path: NodePath, raw: RawData | None,
                   package: str) -> Structure:
        raw = raw or {}
        fields = []
        for name, spec in raw.get('fields', {}).items():
            fpath = path + ('fields', name)
            self.check_name(fpath, 'field', name)
            if isinstance(spec, str):
                spec = {'type': spec}
                tpath = fpath
            else:
                tpath = fpath + ('type',)
            field_type = self._field_type(tpath, spec['type'], package,
                                          f"field '{name}'")
            default = spec.get('default')
            if field_type is not None and 'default' in spec:
                problem = value_problem(field_type, default)
                if problem:
                    # an entry is judged in a list of any length of its type
                    listed = replace(field_type, array='dynamic', array_size=None)
                    self.error_in_list(fpath + ('default',), default, problem,
                                       f"field '{name}': {problem}",
                                       partial(value_problem, listed))
            self._comment(fpath + ('comment',), spec.get('comment', ''),
                          f"field '{name}'")
            if field_type is not None:
                fields.append(Field(name, field_type, default,
                                    spec.get('comment', ''),
                                    self.at(fpath, key=True)))
        constants = []
        for name, spec in raw.get('constants', {}).items():
            cpath = path + ('constants', name)
            self.check_name(cpath, 'constant', name)
            field_type = self._field_type(cpath + ('type',), spec['type'],
                                          package, f"constant '{name}'")
            if field_type is None:
                continue
            if field_type.message is not None or field_type.array is not None:
                self.error(cpath + ('type',), f"constant '{name}' must have a "
                           'primitive, non-array type')
                continue
            problem = value_problem(field_type, spec['value'])
            if problem:
                self.error(cpath + ('value',), f"constant '{name}': {problem}")
            self._comment(cpath + ('comment',), spec.get('comment', ''),
                          f"constant '{name}'")
            constants.append(Constant(name, field_type, spec['value'],
                                      spec.get('comment', ''),
                                      self.at(cpath, key=True)))
        self._comment(path + ('description',), raw.get('description', ''),
                      'the description')
        return Structure(raw.get('description', ''), tuple(fields),
                         tuple(constants))

    def _comment(self, path: NodePath, text: str, what: str) -> None:
        """Refuse text that cannot be a comment of an interface file."""
        problem = interface_comment_problem(text) if text else None
        if problem:
            self.error(path, f'{what} {problem}')
