# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

"""Load every model of a workspace and check what spans several models."""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Iterable, Iterator, Sequence

from colcon_robmosys.errors import Diagnostic, Location, RobmosysError
from colcon_robmosys.model.build import (
    FileBuilder, parameter_value_problem)
from colcon_robmosys.model.index import InterfaceIndex
from colcon_robmosys.model.loader import load_file, LoadedFile
from colcon_robmosys.model.names import connection_name, node_name
from colcon_robmosys.model.qos import qos_incompatibility
from colcon_robmosys.model.schema import check_structure
from colcon_robmosys.model.types import (
    Component, Connection, Instance, InterfaceKind, InterfaceRef, Model,
    ModelFile, Pattern, Port, PortRef, Role, ServiceDefinition, Structure,
    System, Workspace)

MODEL_FILE_NAME = 'robmosys.yaml'


@dataclass
class LoadResult:
    """The valid part of a workspace and every problem found in it."""

    workspace: Workspace
    diagnostics: list[Diagnostic] = field(default_factory=list)
    #: model files whose own content is broken -> the packages, with their
    #: kinds, that each seems to declare
    broken_files: dict[str, list[tuple[str, str]]] = field(
        default_factory=dict)

    @property
    def errors(self) -> list[Diagnostic]:
        """Return the diagnostics of severity error."""
        return [d for d in self.diagnostics if d.severity == 'error']

    def errors_of(self, model_file: str) -> list[Diagnostic]:
        """Return the errors located in one model file."""
        return [d for d in self.errors if d.location.path == model_file]

    #: package -> the warnings about its model
    package_warnings: dict[str, list[Diagnostic]] = field(
        default_factory=dict)

    def warnings_of(self, package: str) -> list[Diagnostic]:
        """Return the warnings about the model of one package."""
        return self.package_warnings.get(package, [])

    def raise_errors(self) -> None:
        """Raise every error at once, if there is any."""
        if self.errors:
            raise RobmosysError(self.errors)


def load_model_file(path: Path) -> ModelFile:
    """Load and check a single file on its own.

    :raises RobmosysError: with every problem of the file
    """
    return check_model_file(load_file(path))


def check_model_file(loaded: LoadedFile) -> ModelFile:
    """Check a loaded file on its own.

    :raises RobmosysError: with every problem of the file
    """
    problems = check_structure(loaded)
    if problems:
        raise RobmosysError(problems)
    builder = FileBuilder(loaded)
    model_file = builder.build()
    if builder.diagnostics:
        raise RobmosysError(builder.diagnostics)
    return model_file


def load_workspace(paths: Iterable[Path],
                   index: InterfaceIndex | None = None) -> LoadResult:
    """Load the model files and check them together.

    Every file is loaded even when others are broken, so that one run
    reports every problem of the workspace.
    """
    files: list[ModelFile] = []
    diagnostics: list[Diagnostic] = []
    broken: dict[str, list[tuple[str, str]]] = {}
    for path in sorted(set(paths)):
        try:
            loaded = load_file(path)
        except RobmosysError as exc:
            diagnostics.extend(exc.diagnostics)
            broken[str(path)] = []
            continue
        try:
            files.append(check_model_file(loaded))
        except RobmosysError as exc:
            diagnostics.extend(exc.diagnostics)
            # read once: a large file is slow to parse
            broken[str(path)] = packages_of(loaded.data)
    checker = _WorkspaceChecker(
        files, index or InterfaceIndex.from_environment(),
        (name for declared in broken.values() for name, _ in declared))
    checker.check()
    diagnostics.extend(checker.diagnostics)
    return LoadResult(Workspace(tuple(files)), sorted(set(diagnostics)),
                      broken, {package: sorted(set(warnings)) for package,
                               warnings in checker.package_warnings.items()})


#: The package kind of each list of models in a file.
MODEL_KINDS = {'service_definitions': 'interfaces', 'components': 'component',
               'systems': 'system'}


def declared_packages(path: Path) -> list[tuple[str, str]]:
    """Return the packages, and their kinds, a broken model file declares.

    As much as can be read: nothing if the file is not even YAML.
    """
    try:
        data = load_file(path).data
    except RobmosysError:
        return []
    return packages_of(data)


def packages_of(data: Any) -> list[tuple[str, str]]:
    """Return the packages, and their kinds, the data of a file declares."""
    if not isinstance(data, dict):
        return []
    return [(model['package'], kind)
            for key, kind in MODEL_KINDS.items()
            if isinstance(data.get(key), list)
            for model in data[key]
            if isinstance(model, dict) and isinstance(model.get('package'), str)]


def find_model_files(base_paths: Sequence[Path]) -> list[Path]:
    """Find the model files below some directories, like colcon would."""
    found = []
    for base in base_paths:
        for path in sorted(Path(base).rglob(MODEL_FILE_NAME)):
            parts = path.relative_to(base).parts
            if any(p in ('build', 'install', 'log') or p.startswith('.')
                   for p in parts[:-1]):
                continue
            found.append(path)
    return found


class _WorkspaceChecker:
    """Checks that need more than one model."""

    def __init__(self, files: Sequence[ModelFile], index: InterfaceIndex,
                 broken_packages: Iterable[str] = ()):
        self.files = files
        self.index = index
        # packages of files with errors of their own: what refers to them
        # is not checked, rather than reported as unknown
        self.broken_packages = frozenset(broken_packages)
        self.diagnostics: list[Diagnostic] = []
        self.package_warnings: dict[str, list[Diagnostic]] = {}
        self.models: dict[str, Model] = {}
        self.definitions: dict[str, ServiceDefinition] = {}
        self.components: dict[str, Component] = {}

    def error(self, location: Location, message: str) -> None:
        self.diagnostics.append(Diagnostic(location, message))

    def warning(self, package: str, location: Location, message: str
                ) -> None:
        diagnostic = Diagnostic(location, message, 'warning')
        self.diagnostics.append(diagnostic)
        self.package_warnings.setdefault(package, []).append(diagnostic)

    def check(self) -> None:
        for model_file in self.files:
            for model in model_file.models:
                other = self.models.get(model.package)
                if other is not None:
                    self.error(model.info.location,
                               f"package '{model.package}' is already "
                               f'generated by the model at '
                               f'{other.info.location}')
                    continue
                self.models[model.package] = model
                if isinstance(model, ServiceDefinition):
                    self.definitions[model.package] = model
                elif isinstance(model, Component):
                    self.components[model.package] = model
        for model in self.models.values():
            if isinstance(model, ServiceDefinition):
                self._check_definition(model)
            elif isinstance(model, Component):
                self._check_component(model)
            else:
                self._check_system(model)
        self._check_cycles()

    # interfaces ---------------------------------------------------------

    def _interface_problem(self, ref: InterfaceRef) -> str | None:
        if ref.package in self.broken_packages:
            return None
        definition = self.definitions.get(ref.package)
        if definition is not None:
            names = {
                InterfaceKind.MSG: [c.name for c in
                                    definition.communication_objects],
                InterfaceKind.SRV: [q.name for q in definition.queries],
                # an event is an action of ROS 2 too
                InterfaceKind.ACTION: [a.name for a in definition.actions] +
                [e.name for e in definition.events],
            }[ref.kind]
            if ref.name in names:
                return None
            known = ', '.join(names) or 'none'
            return (f"unknown type '{ref}': service definition "
                    f"'{ref.package}' defines no {ref.kind.value} "
                    f"'{ref.name}' (its {ref.kind.value} types: {known})")
        if ref.package in self.models:
            return (f"unknown type '{ref}': package '{ref.package}' is not "
                    'a service definition')
        if self.index.has_interface(ref):
            return None
        if self.index.has_package(ref.package):
            return (f"unknown type '{ref}': the installed package "
                    f"'{ref.package}' has no such interface")
        return (f"unknown type '{ref}': package '{ref.package}' is neither "
                'a service definition of this workspace nor installed in '
                'AMENT_PREFIX_PATH')

    def _event_problem(self, port: Port) -> str | None:
        """Tell when an event port names a plain action, or the reverse."""
        definition = self.definitions.get(port.type.package)
        if definition is None or port.pattern not in (Pattern.EVENT,
                                                      Pattern.ACTION):
            return None
        events = {e.name for e in definition.events}
        if port.pattern is Pattern.EVENT and port.type.name not in events:
            return (f"'{port.type}' is an action, not an event: an event "
                    f"port names an entry of 'events' of '{definition.package}'")
        if port.pattern is Pattern.ACTION and port.type.name in events:
            return (f"'{port.type}' is an event: name it from an event port "
                    '(pattern: event)')
        return None

    def _check_definition(self, definition: ServiceDefinition) -> None:
        structures = [o.structure for o in definition.communication_objects]
        structures += [s for q in definition.queries
                       for s in (q.request, q.answer)]
        structures += [s for a in definition.actions
                       for s in (a.goal, a.result, a.feedback)]
        structures += [s for e in definition.events
                       for s in (e.activation, e.event)]
        for structure in structures:
            for field_ in structure.fields:
                ref = field_.type.message
                if ref is None:
                    continue
                problem = self._interface_problem(ref)
                if problem:
                    self.error(field_.location,
                               f"field '{field_.name}': {problem}")

    def _check_component(self, component: Component) -> None:
        for port in component.ports:
            problem = self._interface_problem(port.type) or \
                self._event_problem(port)
            if problem:
                self.error(port.location, f"port '{port.name}': {problem}")
        for package in component.info.depends:
            if package not in self.models and \
                    package not in self.broken_packages and \
                    not self.index.has_package(package):
                self.error(component.info.location,
                           f"component '{component.name}' depends on "
                           f"unknown package '{package}'")

    # systems ------------------------------------------------------------

    def _check_system(self, system: System) -> None:
        components: dict[str, Component] = {}
        node_names: dict[str, str] = {}
        for instance in system.instances:
            if instance.component == system.package:
                self.error(instance.location,
                           f"instance '{instance.name}': package "
                           f"'{instance.component}' is this system itself, "
                           'not a component')
                continue
            component = self.components.get(instance.component)
            if component is None and \
                    instance.component in self.broken_packages:
                continue
            if component is None:
                what = ('is not a component'
                        if instance.component in self.models
                        else 'is not a component of this workspace')
                self.error(instance.location,
                           f"instance '{instance.name}': package "
                           f"'{instance.component}' {what}")
                continue
            components[instance.name] = component
            fqn = node_name(instance.namespace, instance.name)
            if fqn in node_names:
                self.error(instance.location,
                           f"instance '{instance.name}' has the node name "
                           f"'{fqn}' of instance '{node_names[fqn]}'")
            node_names[fqn] = instance.name
            self._check_overrides(instance, component)
            for after in instance.after:
                other = system.instance(after)
                if other is None:
                    self.error(instance.location,
                               f"instance '{instance.name}' is activated "
                               f"after unknown instance '{after}'")
                elif not other.activate or not instance.activate:
                    unmanaged = instance if not instance.activate else other
                    self.error(instance.location,
                               f"instance '{instance.name}' is activated "
                               f"after '{after}', but '{unmanaged.name}' is "
                               'not activated by the system (activate: false)')
        connected: set[tuple[str, str]] = set()
        names = _Names()
        for connection in system.connections:
            ends: list[tuple[PortRef, Port]] = []
            for ref in (connection.source, connection.target):
                component = components.get(ref.instance)
                if system.instance(ref.instance) is None:
                    self.error(ref.location,
                               f"connection end '{ref}': unknown instance "
                               f"'{ref.instance}'")
                elif component is not None:
                    port = component.port(ref.port)
                    if port is None:
                        self.error(ref.location,
                                   f"connection end '{ref}': component "
                                   f"'{component.name}' has no port "
                                   f"'{ref.port}'")
                    else:
                        ends.append((ref, port))
                        connected.add((ref.instance, ref.port))
            if len(ends) == 2 and self._check_connection(
                    connection.location, ends[0][1], ends[1][1]):
                self._check_names(system, connection, ends, names)
        for instance in system.instances:
            component = components.get(instance.name)
            for port in component.ports if component else ():
                if port.role is Role.REQUIRED and \
                        (instance.name, port.name) not in connected:
                    self.warning(system.package, instance.location,
                                 f"required port '{instance.name}."
                                 f"{port.name}' is not connected")

    def _check_connection(self, location: Location, a: Port,
                          b: Port) -> bool:
        """Check that two ports fit; return whether they do."""
        if a.pattern is not b.pattern:
            self.error(location, f'cannot connect {_a(a.pattern.value)} '
                       f"port ('{a.name}') to {_a(b.pattern.value)} port "
                       f"('{b.name}')")
            return False
        if a.role is b.role:
            self.error(location, f'cannot connect two {a.role.value} ports '
                       f"('{a.name}', '{b.name}'): a connection joins a "
                       'provided port to a required one')
            return False
        if a.type != b.type:
            self.error(location, f"type mismatch: '{a.name}' exchanges "
                       f"{a.type}, '{b.name}' exchanges {b.type}")
            return False
        writer, reader = _writer_reader(a, b)
        if writer is not None and reader is not None:
            problem = qos_incompatibility(writer.qos, reader.qos)
            if problem:
                self.error(location, 'incompatible QoS between '
                           f"'{writer.name}' (writer) and '{reader.name}' "
                           f'(reader): {problem}')
                return False
        return True

    def _check_names(self, system: System, connection: Connection,
                     ends: list[tuple[PortRef, Port]], names: _Names) -> None:
        """Check the ROS 2 name a connection remaps its two ends to.

        ROS 2 remaps a name once per node: a port in two connections must
        take one name in both. One name carries one pattern and type, and a
        service or action name has one server.
        """
        ref, port = next(e for e in ends if e[1].role is Role.PROVIDED)
        instance = system.instance(ref.instance)
        assert instance is not None
        name = connection_name(instance.namespace, ref.instance, ref.port,
                               connection.topic)
        here = connection.location
        for end, _ in ends:
            key = (end.instance, end.port)
            if key in names.of_port and names.of_port[key][0] != name:
                other, where = names.of_port[key]
                self.error(here, f"port '{end}' is connected to '{name}' "
                           f"here but to '{other}' by the connection at "
                           f'line {where.line}: ROS 2 remaps a port to one '
                           'name (give both connections the same topic)')
            names.of_port.setdefault(key, (name, here))
        kind = f'{port.pattern.value} ports of {port.type}'
        other_kind, where = names.kind.setdefault(name, (kind, here))
        if other_kind != kind:
            self.error(here, f"'{name}' connects {kind} here but "
                       f'{other_kind} at line {where.line}')
        if port.pattern in (Pattern.QUERY, Pattern.ACTION, Pattern.EVENT):
            server, where = names.server.setdefault(name, (str(ref), here))
            if server != str(ref):
                self.error(here, f"'{name}' is served by '{ref}' here and "
                           f"by '{server}' at line {where.line}: a "
                           f'{port.pattern.value} name has one server')

    def _check_overrides(self, instance: Instance, component: Component) -> None:
        parameters = {p.name: p for p in component.parameters}
        locations = instance.parameter_locations or \
            (instance.location,) * len(instance.parameters)
        for (name, value), location in zip(instance.parameters, locations):
            parameter = parameters.get(name)
            if parameter is None:
                known = ', '.join(sorted(parameters)) or 'none'
                self.error(location,
                           f"instance '{instance.name}': component "
                           f"'{component.name}' has no parameter '{name}' "
                           f'(its parameters: {known})')
                continue
            problem = parameter_value_problem(parameter.type, value)
            if problem is None and parameter.range is not None and \
                    not parameter.range.start <= value <= parameter.range.end:
                problem = (f'{value} is out of the range '
                           f'[{parameter.range.start}, {parameter.range.end}]')
            if problem:
                self.error(location,
                           f"instance '{instance.name}', parameter '{name}': "
                           f'{problem}')

    # cycles -------------------------------------------------------------

    def _check_cycles(self) -> None:
        graph = {name: {d for d in model_dependencies(model)
                        if d in self.models}
                 for name, model in self.models.items()}
        for cycle in _cycles(graph):
            model = self.models[cycle[0]]
            self.error(model.info.location, 'dependency cycle: ' +
                       ' -> '.join(cycle + [cycle[0]]))
        for model in self.models.values():
            if isinstance(model, ServiceDefinition):
                self._check_message_cycles(model)
            if isinstance(model, System):
                order = {i.name: set(i.after) for i in model.instances}
                for cycle in _cycles(order):
                    instance = model.instance(cycle[0])
                    assert instance is not None
                    self.error(instance.location, 'activation order cycle: ' +
                               ' -> '.join(cycle + [cycle[0]]))

    def _check_message_cycles(self, definition: ServiceDefinition) -> None:
        # across packages, a cycle of messages is a dependency cycle too
        objects = {o.name: o for o in definition.communication_objects}
        graph = {name: {f.type.message.name for f in obj.structure.fields
                        if f.type.message is not None and
                        f.type.message.package == definition.package}
                 for name, obj in objects.items()}
        for cycle in _cycles(graph):
            self.error(objects[cycle[0]].location, (
                'message type cycle: ' + ' -> '.join(cycle + [cycle[0]]) +
                ' (a message cannot contain itself, not even through '
                'arrays or other messages)'))


def _a(word: str) -> str:
    """Return a word with its indefinite article."""
    return f"{'an' if word[0] in 'aeiou' else 'a'} {word}"


@dataclass
class _Names:
    """The ROS 2 names the connections of a system have used so far."""

    #: (instance, port) -> its name and the connection that gave it
    of_port: dict[tuple[str, str], tuple[str, Location]] = field(
        default_factory=dict)
    #: name -> the pattern and type of its ports, and where first seen
    kind: dict[str, tuple[str, Location]] = field(default_factory=dict)
    #: service, action or event name -> its server, and where first seen
    server: dict[str, tuple[str, Location]] = field(default_factory=dict)


def _writer_reader(a: Port, b: Port) -> tuple[Port | None, Port | None]:
    """Return which port writes and which reads a topic connection."""
    if a.pattern in (Pattern.QUERY, Pattern.ACTION):
        return None, None
    provided, required = (a, b) if a.role is Role.PROVIDED else (b, a)
    if a.pattern is Pattern.SEND:
        return required, provided
    return provided, required


def model_dependencies(model: Model) -> list[str]:
    """Return the packages a model's generated package depends on."""
    deps: list[str] = list(model.info.depends)
    if isinstance(model, ServiceDefinition):
        for structure in _structures(model):
            for field_ in structure.fields:
                if field_.type.message and \
                        field_.type.message.package != model.package:
                    deps.append(field_.type.message.package)
    elif isinstance(model, Component):
        for port in model.ports:
            deps.append(port.type.package)
    else:
        # an instance of the system itself is an error of its own, not a
        # dependency cycle as well
        deps.extend(i.component for i in model.instances
                    if i.component != model.package)
    return list(dict.fromkeys(deps))


def _structures(definition: ServiceDefinition) -> Iterator[Structure]:
    for obj in definition.communication_objects:
        yield obj.structure
    for query in definition.queries:
        yield query.request
        yield query.answer
    for action in definition.actions:
        yield action.goal
        yield action.result
        yield action.feedback
    for event in definition.events:
        yield event.activation
        yield event.event


def _cycles(graph: dict[str, set[str]]) -> list[list[str]]:
    """Return one cycle per strongly connected part that loops."""
    cycles: list[list[str]] = []
    state: dict[str, int] = {}
    for start in sorted(graph):
        if state.get(start):
            continue
        stack = [(start, iter(sorted(graph.get(start, ()))))]
        path, state[start] = [start], 1
        while stack:
            node, children = stack[-1]
            child = next(children, None)
            if child is None:
                stack.pop()
                path.pop()
                state[node] = 2
            elif state.get(child) == 1:
                cycles.append(path[path.index(child):])
            elif not state.get(child) and child in graph:
                state[child] = 1
                path.append(child)
                stack.append((child, iter(sorted(graph[child]))))
    return cycles
