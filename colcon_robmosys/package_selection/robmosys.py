# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

import os

from colcon_core.logging import colcon_logger
from colcon_core.package_selection import PackageSelectionExtensionPoint
from colcon_core.plugin_system import satisfies_version

from colcon_robmosys.check.index import environ_prefixes
from colcon_robmosys.check.index import search_prefixes
from colcon_robmosys.mapping.backends import PREFIX_PACKAGES
from colcon_robmosys.package_discovery.robmosys import checked_result
from colcon_robmosys.runtime import package_markers

logger = colcon_logger.getChild(__name__)

#: The verbs that build or test packages: the others (list, graph, info,
#: robmosys-generate) show and generate every package.
_BUILDING_VERBS = ('build', 'test')


class RobmosysPackageSelection(PackageSelectionExtensionPoint):
    """Skip components that need what no prefix provides, unless their model has errors.

    What a component needs of the ROS 2 prefix is its language backend's
    (mapping/backends/): rclcpp for C++. rclcpp is not on PyPI: a
    workspace of models still builds everything else on a machine without
    it, and colcon says which packages it skipped and why, instead of
    reporting them as finished.
    """

    # after the selection arguments of the user (colcon-package-selection
    # runs at the default priority): only what they selected is looked at
    PRIORITY = 50

    def __init__(self):  # noqa: D107
        super().__init__()
        satisfies_version(
            PackageSelectionExtensionPoint.EXTENSION_POINT_VERSION, '^1.0')

    def select_packages(self, *, args, decorators):  # noqa: D102
        if getattr(args, 'verb_name', None) not in _BUILDING_VERBS:
            return
        in_workspace = {d.descriptor.name for d in decorators}
        skipped = set()
        #: what is missing -> the packages skipped for it: one warning each
        missing_for: dict[tuple[str, ...], list[str]] = {}
        for decorator in decorators:
            pkg = decorator.descriptor
            if not decorator.selected or pkg.type != 'robmosys.component':
                continue
            depends = pkg.get_dependencies(categories=('build', ))
            needs = [name for name in PREFIX_PACKAGES
                     if name in depends and name not in in_workspace]
            missing = missing_prefix_packages(needs)
            if missing and _has_errors(pkg):
                # its build reports them and fails: a broken model is not
                # let through as skipped
                continue
            if missing:
                decorator.selected = False
                skipped.add(pkg.name)
                missing_for.setdefault(tuple(missing), []).append(pkg.name)
        for missing, names in missing_for.items():
            listed = ', '.join(f"'{name}'" for name in sorted(names))
            logger.warning(
                f'Skipping {listed}: '
                f"{'they need' if len(names) > 1 else 'it needs'} "
                f"{', '.join(missing)}, which no prefix on AMENT_PREFIX_PATH "
                'or CMAKE_PREFIX_PATH provides (source a ROS 2 install that '
                'has them; `colcon robmosys-generate --output-dir DIR` writes '
                f"{'their' if len(names) > 1 else 'its'} sources)")
        # what only runs a skipped component (a system launching it) still
        # builds: colcon would look for the skipped package's install
        if not skipped:
            return
        for decorator in decorators:
            dependencies = decorator.descriptor.dependencies
            for category, names in dependencies.items():
                dependencies[category] = {
                    d for d in names if d not in skipped}
            # the build verb reads these, computed before the selection
            recursive = getattr(decorator, 'recursive_dependencies', None)
            if recursive is not None:
                decorator.recursive_dependencies = [
                    d for d in recursive if d not in skipped]


def _has_errors(pkg):
    """Return whether the model of a package of ours has errors (the check runs now)."""
    model_file = pkg.metadata['robmosys_model_file']
    result = checked_result(pkg)
    return bool(result.errors_of(model_file)) or model_file in result.broken_files


def missing_prefix_packages(names, dependency_prefixes=(), environ=None):
    """Return the packages among names that no prefix provides.

    A package counts as provided if a prefix of AMENT_PREFIX_PATH,
    CMAKE_PREFIX_PATH or of the package's dependencies in the workspace has
    its ament index entry or its CMake config file, which is what
    find_package() will look for.
    """
    environ = os.environ if environ is None else environ
    prefixes = list(dependency_prefixes) + \
        environ_prefixes(environ, 'AMENT_PREFIX_PATH') + \
        environ_prefixes(environ, 'CMAKE_PREFIX_PATH')
    return [name for name in names
            if search_prefixes(prefixes, package_markers(name)) is None]
