# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""Synthetic workspaces for the benchmarks: N components, their messages and systems.

Components come in groups of ten (fewer in a last, smaller group). Each group has
a service definition (two messages and a query) that its components exchange, and
a system that connects the group's components in a ring. Every component has a
publisher and a subscription, a periodic and a triggered activity, functions with
code and without (so an implementation file of the user's), a lifecycle hook and
three parameters: the features a real component uses, in the same proportion at
every N.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
import shutil
import sys
from typing import Any

import yaml

from colcon_robmosys.check import find_model_files, load_workspace
from colcon_robmosys.check.index import InterfaceIndex
from colcon_robmosys.generators import create_missing_user_files, generate_package
from colcon_robmosys.generators import plan_package
from colcon_robmosys.mapping.common import RUNTIME_PACKAGE
from colcon_robmosys.runtime import runtime_source

GROUP = 10
METADATA = {
    'license': 'Apache-2.0',
    'maintainers': [{'name': 'Benchmark Team', 'email': 'bench@example.com'}],
}


@dataclass(frozen=True)
class WorkspaceShape:
    """How many packages of each kind a synthetic workspace holds."""

    components: int
    service_definitions: int
    systems: int

    @property
    def packages(self) -> int:
        """Return the number of packages the workspace generates."""
        return self.components + self.service_definitions + self.systems


def _service_definition(package: str) -> dict[str, Any]:
    return {
        'package': package,
        'description': 'Messages the components of one group exchange.',
        'communication_objects': {
            'Sample': {
                'description': 'One sample of a component.',
                'fields': {
                    'stamp_ns': {'type': 'int64', 'comment': 'When it was taken.'},
                    'seq': 'uint64',
                    'values': 'float64[]',
                    'label': {'type': 'string<=32', 'default': 'none'},
                    'status': 'Status',
                },
            },
            'Status': {
                'constants': {'OK': {'type': 'uint8', 'value': 0},
                              'FAILED': {'type': 'uint8', 'value': 1}},
                'fields': {'code': 'uint8', 'text': 'string'},
            },
        },
        'queries': {
            'GetStatus': {
                'request': {'fields': {'verbose': 'bool'}},
                'answer': {'fields': {'status': 'Status'}},
            },
        },
    }


#: The code of the functions with code, per language.
CODE = {
    'python': {'fSetUp': 'self.sample = {type}()\n',
               'fPublish': 'self.pOut.publish(self.sample)\n'},
    'cpp': {'fSetUp': 'sample_ = {cpp_type}();\n',
            'fPublish': 'pOut_->publish(sample_);\n'},
}


def _component(package: str, name: str, msg_type: str,
               language: str = 'python') -> dict[str, Any]:
    type_name = msg_type.rsplit('/', 1)[-1]
    code = {function: text.format(type=type_name,
                                  cpp_type=msg_type.replace('/', '::'))
            for function, text in CODE[language].items()}
    return {
        'name': name,
        'package': package,
        'language': language,
        'description': f'Synthetic component {name}: publishes samples, handles others.',
        'ports': {
            'pOut': {'pattern': 'push', 'role': 'provided', 'type': msg_type,
                     'qos': {'depth': 5}},
            'rIn': {'pattern': 'push', 'role': 'required', 'type': msg_type,
                    'qos': {'depth': 5, 'reliability': 'reliable'}},
        },
        'activities': {
            'Tick': {'period': 0.1, 'functions': ['fFill', 'fPublish']},
            'OnSample': {'trigger': 'rIn', 'functions': ['fOnSample']},
        },
        'functions': {
            'fSetUp': {'code': code['fSetUp']},
            'fFill': {'description': 'Fill the sample from the sensors.'},
            'fPublish': {'code': code['fPublish']},
            'fOnSample': {'description': 'Handle a sample of the previous component.'},
        },
        'lifecycle': {'on_configure': ['fSetUp']},
        'parameters': {
            'rate': {'type': 'double', 'default': 10.0, 'range': {'from': 0.1, 'to': 100.0},
                     'description': 'Samples per second.'},
            'label': {'type': 'string', 'default': name, 'read_only': True},
            'gains': {'type': 'double[]', 'default': [1.0, 2.0]},
        },
    }


def _system(package: str, components: list[str]) -> dict[str, Any]:
    instances = {f'n{i}': {'component': c, 'parameters': {'rate': 5.0}}
                 for i, c in enumerate(components)}
    count = len(components)
    connections = [{'from': f'n{i}.pOut', 'to': f'n{(i + 1) % count}.rIn'}
                   for i in range(count)]
    return {'package': package, 'name': 'Ring',
            'description': 'The components of one group, connected in a ring.',
            'instances': instances, 'connections': connections}


def _write_model(src: Path, package: str, key: str, model: dict[str, Any]) -> Path:
    path = src / package / 'robmosys.yaml'
    path.parent.mkdir(parents=True)
    document = {'robmosys': 1, 'defaults': METADATA, key: [model]}
    path.write_text(yaml.safe_dump(document, sort_keys=False), encoding='utf-8')
    return path


def write_workspace(src: Path, components: int, *, own_messages: bool = True,
                    cpp_every: int = 0) -> WorkspaceShape:
    """Write the model files of a synthetic workspace, one folder per model, into src.

    :param own_messages: give each group a service definition of its own; without,
      components exchange ``std_msgs/msg/Header`` and nothing needs rosidl
    :param cpp_every: make every cpp_every-th component a C++ one (0: none)
    """
    groups = (components + GROUP - 1) // GROUP
    for group in range(groups):
        size = min(GROUP, components - group * GROUP)
        msg_package = f'bench_g{group}_msgs'
        if own_messages:
            _write_model(src, msg_package, 'service_definitions',
                         _service_definition(msg_package))
            msg_type = f'{msg_package}/msg/Sample'
        else:
            msg_type = 'std_msgs/msg/Header'
        packages = []
        for index in range(size):
            package = f'bench_g{group}_c{index}'
            number = group * GROUP + index
            language = 'cpp' if cpp_every and number % cpp_every == cpp_every - 1 \
                else 'python'
            _write_model(src, package, 'components',
                         _component(package, f'Node{group}x{index}', msg_type, language))
            packages.append(package)
        _write_model(src, f'bench_g{group}_system', 'systems',
                     _system(f'bench_g{group}_system', packages))
    return WorkspaceShape(components, groups if own_messages else 0, groups)


def ros_index() -> InterfaceIndex:
    """Return the index of the interfaces installed in this venv (std_msgs and others)."""
    return InterfaceIndex([Path(sys.prefix)])


def write_handwritten(models_src: Path, dest_src: Path) -> int:
    """Write, as plain ament packages, what the models of models_src generate.

    The result is what a team would write by hand to get the same packages:
    the generated files and the user's implementation files, without any model.
    Creates the missing implementation files next to the models too, as
    ``colcon robmosys-generate`` does, so that models_src builds.

    :returns: the number of packages written, the runtime package included
    """
    result = load_workspace(find_model_files([models_src]), ros_index())
    result.raise_errors()
    count = 0
    for model in result.workspace.models:
        plan = plan_package(result.workspace, model.package)
        create_missing_user_files(plan)
        generate_package(plan, dest_src / model.package)
        count += 1
    # the runtime the generated components use, as a package of its own: a
    # team would vendor it, as colcon-robmosys adds it to the models' workspace
    shutil.copytree(runtime_source(), dest_src / RUNTIME_PACKAGE,
                    ignore=shutil.ignore_patterns('__pycache__'))
    return count + 1
