# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

from pathlib import Path
import threading

from colcon_core.dependency_descriptor import DependencyDescriptor
from colcon_core.logging import colcon_logger
from colcon_core.package_descriptor import PackageDescriptor
from colcon_core.package_discovery import PackageDiscoveryExtensionPoint
from colcon_core.plugin_system import satisfies_version

from colcon_robmosys.check import load_workspace
from colcon_robmosys.check.cache import CACHE_DIR
from colcon_robmosys.check.cache import ModelCache
from colcon_robmosys.errors import print_diagnostics
from colcon_robmosys.mapping.backends import prefix_dependencies
from colcon_robmosys.mapping.common import RUNTIME_PACKAGE
from colcon_robmosys.mapping.portkinds import port_kind
from colcon_robmosys.mapping.portkinds import PORT_KINDS
from colcon_robmosys.model.files import model_dependencies
from colcon_robmosys.model.outline import NoOutline
from colcon_robmosys.model.outline import outline_file
from colcon_robmosys.model.outline import with_subsystems
from colcon_robmosys.model.types import Component
from colcon_robmosys.model.types import ServiceDefinition
from colcon_robmosys.package_identification.robmosys import \
    RobmosysPackageIdentification
from colcon_robmosys.runtime import installed_runtime
from colcon_robmosys.runtime import runtime_source

logger = colcon_logger.getChild(__name__)

#: Where a package descriptor keeps the loaded workspace.
METADATA_KEY = 'robmosys'


class CheckedModels:
    """The checked workspace, shared by the descriptors of its packages.

    Checked when first asked for (the build of a package, robmosys-generate),
    once for all of them, and its errors printed then; discovery itself only
    outlines the model files (model/outline.py), unless an outline cannot
    tell what the check would.

    ``colcon info`` prints every metadata value: this one reads as a line,
    not as the whole workspace.
    """

    __slots__ = ('_model_files', '_cache', '_result', '_lock')

    def __init__(self, model_files, cache):  # noqa: D107
        self._model_files = model_files
        self._cache = cache
        self._result = None
        self._lock = threading.Lock()

    @property
    def result(self):
        """Return the check stage's result, checking the workspace the first time."""
        return self.checked()

    def checked(self, workers=1):
        """Return the check stage's result, checking the workspace the first time.

        :param workers: the most processes to check in at once, forked (a
          verb that runs no thread beside its own: robmosys-generate)
        """
        with self._lock:
            if self._result is None:
                self._result = load_workspace(
                    self._model_files, cache=self._cache, workers=workers)
                # bare compiler-style lines, once; warnings are told by the
                # build of their package and by robmosys-generate, and only
                # for the packages selected
                print_diagnostics(
                    d for d in self._result.diagnostics
                    if d.severity == 'error')
            return self._result

    def __str__(self):
        # what colcon info prints: the check's verdict
        result = self.result
        return (f'{len(result.workspace.models)} checked models, '
                f'{len(result.errors)} error(s)')

    def __repr__(self):
        state = 'checked' if self._result is not None else 'not checked yet'
        return f'<CheckedModels of {len(self._model_files)} model files, {state}>'


def checked_result(descriptor, workers=1):
    """Return the check stage's result a descriptor of ours carries.

    :param workers: the most processes to check in at once, forked, if the
      workspace is not checked yet (see :meth:`CheckedModels.checked`)
    """
    return descriptor.metadata[METADATA_KEY].checked(workers)


class RobmosysPackageDiscovery(PackageDiscoveryExtensionPoint):
    """Turn every recorded model file into one package per model.

    Discovery reads what colcon needs of each model (names, kinds,
    dependencies) from outlines of the files; the models of the whole
    workspace are loaded and checked together, since components use service
    definitions and systems use components, once, by the first build of a
    package or by robmosys-generate. Nothing is written: files are only
    written by the build and the verb.
    """

    # after the crawling discovery extensions (100 and up) have identified
    # every folder
    PRIORITY = 10

    def __init__(self):  # noqa: D107
        super().__init__()
        satisfies_version(
            PackageDiscoveryExtensionPoint.EXTENSION_POINT_VERSION, '^1.0')

    def has_parameters(self, *, args):  # noqa: D102
        # passive: runs along with whichever discovery the user chose
        return None

    def discover(self, *, args, identification_extensions):  # noqa: D102
        model_files, runtime_folders = set(), set()
        for extensions_same_prio in identification_extensions.values():
            for extension in extensions_same_prio.values():
                if isinstance(extension, RobmosysPackageIdentification):
                    model_files |= extension.model_files
                    runtime_folders |= extension.runtime_folders
        if not model_files:
            return set()
        shared = CheckedModels(model_files, model_cache(args))
        outlines = outline_workspace(model_files)
        if outlines is None:
            # the check tells what the packages are: now, whatever the verb,
            # and its errors with it
            descriptors = checked_descriptors(shared.result, model_files, shared)
        else:
            descriptors = outlined_descriptors(outlines, shared)
        if not runtime_folders and _runtime_needed(args):
            descriptors.add(_runtime_descriptor())
        return descriptors


def outline_workspace(model_files):
    """Return the outlines of the model files, or None where only the check can tell.

    None also for two files declaring one package or for a dependency cycle:
    the check reports each with its lines, where colcon would only stop.
    """
    outlines, names = {}, {}
    for model_file in sorted(model_files):
        try:
            outlines[model_file] = outline_file(model_file)
        except NoOutline:
            logger.debug(f"'{model_file}' is checked to tell its packages")
            return None
        for package in outlines[model_file]:
            if names.setdefault(package.name, package) is not package:
                return None
    if _has_cycle({name: [d for d in package.dependencies if d in names]
                   for name, package in names.items()}):
        return None
    expanded = with_subsystems(names)
    return {model_file: [expanded[p.name] for p in packages]
            for model_file, packages in outlines.items()}


def outlined_descriptors(outlines, shared):
    """Return the descriptors of the packages the outlines of the model files name."""
    return {
        _descriptor(model_file, o.name, o.kind, _dependencies(
            o.kind, o.dependencies,
            prefix_dependencies(o.language, (PORT_KINDS[p] for p in o.ports))),
            shared)
        for model_file, packages in outlines.items() for o in packages}


def _has_cycle(graph):
    """Return whether a graph (node -> successors) has a cycle."""
    # Kahn: what never gets to no remaining predecessor lies on a cycle
    waiting = dict.fromkeys(graph, 0)
    for successors in graph.values():
        for node in successors:
            waiting[node] += 1
    ready = [node for node, count in waiting.items() if not count]
    done = 0
    while ready:
        done += 1
        for node in graph[ready.pop()]:
            waiting[node] -= 1
            if not waiting[node]:
                ready.append(node)
    return done < len(graph)


def _dependencies(kind, dependencies, prefix=()):
    """Return a generated package's dependencies: its model's, the runtime, the prefix's.

    :param prefix: what a component's language needs of the ROS 2 prefix
      (a C++ component's rclcpp packages), built before it if the workspace
      builds them itself; the package selection skips the component where
      none has them
    """
    dependencies = tuple(dependencies)
    if kind in ('component', 'system'):
        # components run on it; systems activate with it
        dependencies += (RUNTIME_PACKAGE, )
    return dependencies + tuple(prefix)


def checked_descriptors(result, model_files, shared):
    """Return the descriptors of the packages the check stage found."""
    descriptors = set()
    # not external components (a hand-written package), nor models an
    # underlay installed (built there)
    for model in result.workspace.generated_models:
        kind = 'interfaces' if isinstance(model, ServiceDefinition) else \
            'component' if isinstance(model, Component) else 'system'
        descriptors.add(_descriptor(
            model.info.model_file, model.package, kind,
            _dependencies(kind, model_dependencies(model),
                          prefix_dependencies(
                              model.language, (port_kind(p) for p in model.ports))
                          if isinstance(model, Component) else ()),
            shared))
    generating = {m.info.model_file for m in
                  result.workspace.generated_models}
    for model_file, declared in sorted(result.broken_files.items()):
        # the build of these packages reports the errors and fails;
        # a file too broken to name any is named after its folder,
        # unless a package it generates reports them (a broken external
        # component beside a system)
        if not declared and model_file in generating:
            continue
        for name, kind in declared or [
                (Path(model_file).parent.name, 'invalid')]:
            descriptors.add(
                _descriptor(model_file, name, kind, (), shared))
    # a file of external models only (nothing generated) with errors:
    # named after its folder too, so that a build reports them and fails
    ours = {str(path) for path in model_files}
    for model_file in sorted({d.location.path for d in result.errors} &
                             ours - generating -
                             result.broken_files.keys()):
        descriptors.add(_descriptor(
            model_file, Path(model_file).parent.name, 'invalid', (),
            shared))
    return descriptors


def model_cache(args):
    """Return the cache of checked model files in the build base, if any.

    ``colcon build`` (and ``colcon test``) and ``colcon robmosys-generate``
    keep it up to date; ``colcon list``, ``colcon graph``, the others and
    ``robmosys-generate --validate-only`` only read it, if there is one in
    ``build/``: they write nothing.
    """
    build_base = getattr(args, 'build_base', None)
    verb = getattr(args, 'verb_name', None)
    writable = build_base is not None and (
        verb in ('build', 'test') or verb == 'robmosys-generate' and not (
            getattr(args, 'validate_only', False) or
            getattr(args, 'print_schema_path', False)))
    folder = Path(build_base or 'build') / CACHE_DIR
    if not writable and not folder.is_dir():
        return None
    return ModelCache(folder, writable=writable)


def _runtime_needed(args):
    """Return whether no underlay provides robmosys_runtime.

    The install folder of this workspace is no underlay: the runtime it holds
    is this workspace's own build of our package data, rebuilt with it.
    """
    install_base = Path(getattr(args, 'install_base', None) or 'install')
    provider = installed_runtime(ignored=[install_base])
    if provider is not None:
        logger.debug(f"'{RUNTIME_PACKAGE}' is provided by '{provider}'")
    return provider is None


def _runtime_descriptor():
    """Return the descriptor of the runtime package of our package data.

    It is an ordinary ament_cmake package: colcon-ros reads its package.xml
    (its dependencies) and builds and tests it.
    """
    desc = PackageDescriptor(runtime_source())
    desc.type = 'ros.ament_cmake'
    desc.name = RUNTIME_PACKAGE
    return desc


def _descriptor(model_file, name, kind, dependencies, shared):
    desc = PackageDescriptor(Path(model_file).parent)
    desc.type = f'robmosys.{kind}'
    desc.name = name
    for category in ('build', 'run'):
        desc.dependencies[category] = {
            DependencyDescriptor(d) for d in dependencies}
    desc.metadata[METADATA_KEY] = shared
    desc.metadata['robmosys_model_file'] = str(model_file)
    return desc
