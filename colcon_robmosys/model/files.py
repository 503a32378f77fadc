# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

"""Model files: where they are, what packages they declare, what each needs."""

from __future__ import annotations

from pathlib import Path
from typing import Any, Iterator, Sequence

from colcon_robmosys.errors import RobmosysError
from colcon_robmosys.model.loader import load_file
from colcon_robmosys.model.types import Component, Model, ServiceDefinition, Structure

MODEL_FILE_NAME = 'robmosys.yaml'

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
    """Return the packages, and their kinds, the data of a file generates.

    An external component generates none: its package is the user's own.
    """
    if not isinstance(data, dict):
        return []
    return [(model['package'], kind)
            for key, kind in MODEL_KINDS.items()
            if isinstance(data.get(key), list)
            for model in data[key]
            if isinstance(model, dict) and isinstance(model.get('package'), str)
            and not model.get('external')]


def external_components_of(data: Any) -> list[str]:
    """Return the external components (``package/executable``) the data of a file describes."""
    components = data.get('components') if isinstance(data, dict) else None
    return [f"{model['package']}/{model['external']['executable']}"
            for model in (components if isinstance(components, list) else ())
            if isinstance(model, dict) and isinstance(model.get('package'), str)
            and isinstance(model.get('external'), dict)
            and isinstance(model['external'].get('executable'), str)]


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
        # an external component is package/executable: the package is the dependency
        deps.extend(i.component.split('/')[0] for i in model.instances
                    if i.component != model.package)
        # a change of a subsystem's model changes this system's package
        deps.extend(s.system for s in model.subsystems if s.system != model.package)
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
