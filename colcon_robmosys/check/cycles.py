# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

"""Rules on cycles: of package dependencies, messages and activation order."""

from __future__ import annotations

from colcon_robmosys.check.context import CheckContext
from colcon_robmosys.model.files import model_dependencies
from colcon_robmosys.model.types import ServiceDefinition, System


def check_dependency_cycles(ctx: CheckContext) -> None:
    """Check that no package depends on itself, through others or directly."""
    graph = {name: {d for d in model_dependencies(model)
                    if d in ctx.models}
             for name, model in ctx.models.items()}
    for cycle in _cycles(graph):
        model = ctx.models[cycle[0]]
        ctx.error(model.info.location, 'dependency cycle: ' +
                  ' -> '.join(cycle + [cycle[0]]))


def check_message_cycles(ctx: CheckContext) -> None:
    """Check that no message of a service definition contains itself."""
    for model in ctx.models.values():
        if isinstance(model, ServiceDefinition):
            _check_message_cycles(ctx, model)


def check_activation_cycles(ctx: CheckContext) -> None:
    """Check that no instance of a system is activated after itself."""
    for model in ctx.models.values():
        if isinstance(model, System):
            order = {i.name: set(i.after) for i in model.instances}
            for cycle in _cycles(order):
                instance = model.instance(cycle[0])
                assert instance is not None
                # the entry of its 'after' that the cycle goes on through
                where = instance.after_location(cycle[1 % len(cycle)])
                ctx.error(where, 'activation order cycle: ' +
                          ' -> '.join(cycle + [cycle[0]]))


def _check_message_cycles(ctx: CheckContext, definition: ServiceDefinition) -> None:
    # across packages, a cycle of messages is a dependency cycle too
    objects = {o.name: o for o in definition.communication_objects}
    graph = {name: {f.type.message.name for f in obj.structure.fields
                    if f.type.message is not None and
                    f.type.message.package == definition.package}
             for name, obj in objects.items()}
    for cycle in _cycles(graph):
        ctx.error(objects[cycle[0]].location, (
            'message type cycle: ' + ' -> '.join(cycle + [cycle[0]]) +
            ' (a message cannot contain itself, not even through '
            'arrays or other messages)'))


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
