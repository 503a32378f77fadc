# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

"""What the builders of a file's kinds share: where problems are recorded."""

from __future__ import annotations

from typing import Any, Callable, Iterable, Sequence

from colcon_robmosys.errors import Diagnostic, Location
from colcon_robmosys.model import names
from colcon_robmosys.model.loader import LoadedFile, NodePath, RawData
from colcon_robmosys.model.types import Maintainer, PackageInfo

DEFAULT_VERSION = '0.1.0'

#: The lists of models of a file; (section, index) names a model in it.
MODEL_SECTIONS = ('service_definitions', 'components', 'systems')


class BuilderBase:
    """Record problems at the nodes of a loaded file, model by model.

    The builders of one file (model/build.py) record into the same lists.
    """

    def __init__(self, loaded: LoadedFile, diagnostics: list[Diagnostic] | None = None,
                 broken_models: set[tuple[str, int]] | None = None) -> None:
        self.loaded = loaded
        self.diagnostics: list[Diagnostic] = [] if diagnostics is None else diagnostics
        #: (section, index) of the models a problem was found in
        self.broken_models: set[tuple[str, int]] = \
            set() if broken_models is None else broken_models

    def error(self, path: NodePath, message: str, *, key: bool = False) -> None:
        """Record a problem at the node of that path, and its model as broken."""
        self.diagnostics.append(
            Diagnostic(self.loaded.location(path, key=key), message))
        if len(path) >= 2 and path[0] in MODEL_SECTIONS and \
                isinstance(path[1], int):
            self.broken_models.add((str(path[0]), path[1]))

    def at(self, path: NodePath, *, key: bool = False) -> Location:
        """Return the location of a node."""
        return self.loaded.location(path, key=key)

    def at_each(self, path: NodePath, listed: Sequence[Any]) -> tuple[Location, ...]:
        """Return where each entry of the list at that path stands, in order.

        A rule about one entry (an unknown name, a value out of range) points
        at the entry, in block style (``- name`` on a line of its own) as in
        flow style (``[a, name]``).
        """
        return tuple(self.at(path + (index,)) for index in range(len(listed)))

    def error_in_list(self, path: NodePath, value: Any, problem: str, message: str,
                      problem_of: Callable[[list[Any]], str | None]) -> None:
        """Record a problem of a value at the entry it is about, if it is a list's.

        :param message: what to say, ``problem`` and the thing it is about
        """
        index = entry_at_fault(value, problem, problem_of)
        self.error(path if index is None else path + (index,), message)

    def check_name(self, path: NodePath, kind: str, name: str, *,
                   key: bool = True) -> None:
        """Report a name that its kind cannot have (see names.name_problem)."""
        problem = names.name_problem(kind, name)
        if problem:
            self.error(path, problem, key=key)

    # package metadata ---------------------------------------------------

    def _info(self, path: NodePath, raw: RawData, defaults: RawData,
              kind: str) -> PackageInfo:
        name = raw['package']
        self.check_name(path + ('package',), 'package', name, key=False)
        maintainers = raw.get('maintainers', defaults.get('maintainers'))
        license_ = raw.get('license', defaults.get('license'))
        if not maintainers:
            self.error(path, f"{kind} '{name}' lacks 'maintainers' (set them "
                       "in the model or in the file's 'defaults')")
        if not license_:
            self.error(path, f"{kind} '{name}' lacks 'license' (set it in the "
                       "model or in the file's 'defaults')")
        # the schema makes it a string
        version: str = raw['version'] if 'version' in raw else \
            defaults['version'] if 'version' in defaults else DEFAULT_VERSION
        return PackageInfo(
            name=name,
            description=raw.get('description', '').strip() or
            f'The {kind} {name}, generated from a RobMoSys model.',
            version=version,
            license=license_ or '',
            maintainers=tuple(Maintainer(m['name'], m['email'])
                              for m in maintainers or ()),
            depends=tuple(raw.get('depends', ())),
            model_file=str(self.loaded.path),
            location=self.at(path + ('package',)),
            depends_locations=self.at_each(path + ('depends',), raw.get('depends', ())),
            system_depends=tuple(raw.get('system_depends', ())),
        )


def entry_at_fault(values: Any, problem: str,
                   problem_of: Callable[[list[Any]], str | None]) -> int | None:
    """Return the index of the entry of a list value that a problem is about, if one is.

    That is the first entry which, alone in a list, has the very same problem
    (an element out of range, of the wrong kind, not one of those allowed);
    a problem of the list as a whole (its length) is none of its entries'.

    :param problem_of: says what is wrong with a list value, None if nothing
    """
    if not isinstance(values, list):
        return None
    return next((index for index, value in enumerate(values)
                 if problem_of([value]) == problem), None)


def choices(known: Iterable[str]) -> str:
    """Say which names are known, for a message about an unknown one."""
    if not known:
        return ' (none is defined)'
    return f" (known: {', '.join(sorted(known))})"
