# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

import argparse
import os
from pathlib import Path
import sys

from colcon_core.package_selection import add_arguments \
    as add_packages_arguments
from colcon_core.package_selection import get_packages
from colcon_core.plugin_system import satisfies_version
from colcon_core.verb import VerbExtensionPoint

from colcon_robmosys.check.cache import CACHE_DIR
from colcon_robmosys.check.forked import MIN_FILES_PER_WORKER
from colcon_robmosys.errors import print_diagnostics
from colcon_robmosys.errors import RobmosysError
from colcon_robmosys.generators import Durable
from colcon_robmosys.generators import StampStore
from colcon_robmosys.generators import write_tree
from colcon_robmosys.mapping.common import RUNTIME_PACKAGE
from colcon_robmosys.mapping.distributions import distribution_problem
from colcon_robmosys.model.schema import schema_path
from colcon_robmosys.package_discovery.robmosys import checked_result
from colcon_robmosys.report import report_problem
from colcon_robmosys.report import write_report
from colcon_robmosys.runtime import installed_runtime
from colcon_robmosys.runtime import runtime_source
from colcon_robmosys.verb import add_diagnostics_arguments
from colcon_robmosys.verb import diagnostics_request
from colcon_robmosys.verb import display_path
from colcon_robmosys.verb.generation import generate_packages
from colcon_robmosys.verb.generation import Package
from colcon_robmosys.verb.generation import parallel_workers


class RobmosysGenerateVerb(VerbExtensionPoint):
    """Generate ROS 2 packages from RobMoSys models, without building.

    Creates the implementation files a model asks for and that do not exist
    yet, next to the model; existing files are never touched.
    """

    def __init__(self):  # noqa: D107
        super().__init__()
        satisfies_version(VerbExtensionPoint.EXTENSION_POINT_VERSION, '^1.0')

    def add_arguments(self, *, parser):  # noqa: D102
        what = parser.add_mutually_exclusive_group()
        what.add_argument(
            '--output-dir', metavar='DIR', type=Path,
            help='Write the generated packages to DIR/<package> (by default '
            'nothing but the missing implementation files is written)')
        what.add_argument(
            '--export', metavar='DIR', type=Path,
            help='Write the selected packages to DIR/<package> as standalone '
            'ament packages, with robmosys_runtime when they use it: they '
            'build with plain colcon, without colcon-robmosys (for a release '
            'with bloom, or a repository without models)')
        what.add_argument(
            '--validate-only', action='store_true',
            help='Check the models and write nothing; exit non-zero on errors')
        what.add_argument(
            '--print-schema-path', action='store_true',
            help='Print the path of the JSON Schema of robmosys.yaml files '
            'installed with colcon-robmosys (for the settings of an editor) '
            'and exit')
        parser.add_argument(
            '--build-base', default='build',
            help='The base path of the build tree, where the checked models are '
            'cached and what each generation read is recorded, as colcon build '
            'keeps them (default: build)')
        parser.add_argument(
            '--parallel-workers', metavar='NUMBER', type=_positive,
            help='The most processes generating packages at once (default: '
            'the CPUs this process may use; a worker is forked for every '
            f'{MIN_FILES_PER_WORKER} model files at most, and 1 generates '
            'everything in this process)')
        add_diagnostics_arguments(parser)
        add_packages_arguments(parser)

    def main(self, *, context):  # noqa: D102
        args = context.args
        if args.print_schema_path:
            print(schema_path())
            return 0
        request = diagnostics_request(args)
        if request is not None and report_problem(request.path):
            print(report_problem(request.path), file=sys.stderr)
            return 1
        # what the run checked and found, for the report
        files, found = set(), []
        status = self._generate(args, files, found)
        if request is not None:
            try:
                write_report(request, files, found)
            except OSError as error:
                print(f'{display_path(request.path)}: error: cannot write the '
                      f'report: {error.strerror}', file=sys.stderr)
                return 1
        return status

    def _generate(self, args, files, found):
        decorators = get_packages(args)
        selected = [
            d.descriptor for d in decorators
            if d.selected and d.descriptor.type.startswith('robmosys.')]
        if not selected:
            if args.export is not None:
                _say_not_exported(decorators, [], uses_runtime=False)
            print('No RobMoSys model selected', file=sys.stderr)
            return 0
        workers = parallel_workers(args.parallel_workers)
        result = checked_result(selected[0], workers)
        warnings = [w for d in selected for w in result.warnings_of(d.name)]
        print_diagnostics(warnings)
        model_files = {d.metadata['robmosys_model_file'] for d in selected}
        errors = [e for e in result.errors
                  if e.location.path in model_files]
        files.update(model_files)
        found += warnings + errors
        broken = model_files & result.broken_files.keys()
        if errors or broken:
            # discovery has printed every error already; a second
            # call prints nothing, unless the errors came some other way
            print_diagnostics(errors)
            print(f'{len(errors)} error(s) in the selected models',
                  file=sys.stderr)
            return 1
        if args.validate_only:
            print(f'{len(selected)} package(s) valid: ' +
                  ', '.join(sorted(d.name for d in selected)))
            return 0
        problem = distribution_problem(os.environ)
        if problem:
            # generated all the same: the files can be read, or exported and
            # built on another machine; colcon build refuses
            print(f'warning: {problem}', file=sys.stderr)
        out_base = args.output_dir
        if args.export is not None:
            problem = _export_problem(args.export, args)
            if problem:
                print(problem, file=sys.stderr)
                return 1
            out_base = args.export
        elif args.output_dir is not None:
            # as colcon marks build/ and install/: the generated packages
            # must not be found as packages of the workspace next time
            args.output_dir.mkdir(parents=True, exist_ok=True)
            marker = args.output_dir / 'COLCON_IGNORE'
            if not marker.exists():
                # created once: touching it would change its mtime on
                # every run, and a run with no change changes nothing
                marker.touch()
        # the cache of the checked models holds the stamps of the packages
        # generated (as a build's): a package whose inputs have not changed
        # since is neither planned nor rendered again
        outcome = generate_packages(result, [
            Package(d.name, d.metadata['robmosys_model_file'],
                    None if out_base is None else out_base / d.name,
                    RUNTIME_PACKAGE in d.get_dependencies())
            for d in selected], StampStore(Path(args.build_base) / CACHE_DIR / 'stamps'),
            workers)
        found += outcome.found
        status, uses_runtime = outcome.status, outcome.uses_runtime
        if args.export is not None:
            _say_not_exported(decorators, selected, uses_runtime=uses_runtime)
        provider = installed_runtime(
            ignored=[Path(getattr(args, 'install_base', None) or 'install')])
        if args.export is not None and uses_runtime and provider is not None:
            # a release of its own (a binary package, say): the export
            # depends on it as on any other package of the underlay
            print(f'not exported: {RUNTIME_PACKAGE}, which '
                  f'{display_path(provider)} provides')
        elif args.export is not None and uses_runtime and status == 0:
            out = args.export / RUNTIME_PACKAGE
            try:
                exported = Durable()
                report = write_tree(_runtime_files(), out, durable=exported)
                exported.commit()
            except RobmosysError as error:
                print_diagnostics(error.diagnostics)
                found += error.diagnostics
                return 1
            print(f'exported {RUNTIME_PACKAGE} in {display_path(out)}: '
                  f'{len(report.written)} written, '
                  f'{len(report.unchanged)} unchanged, '
                  f'{len(report.removed)} removed')
        return status


def _say_not_exported(decorators, models, *, uses_runtime):
    """Say, once per package, which packages of the selection are not exported, and why.

    An export holds what models generate. A hand-written package of the
    selection is its own source already: the user releases it from there.
    robmosys_runtime goes along when an exported package uses it (the lines
    about it follow); selected for a hand-written package alone, it does not.

    :param decorators: the package decorators of the run
    :param models: the descriptors of the selected models
    :param uses_runtime: whether an exported package uses robmosys_runtime
    """
    others = {d.descriptor.name: d.descriptor for d in decorators
              if d.selected and not d.descriptor.type.startswith('robmosys.')}
    if others.pop(RUNTIME_PACKAGE, None) is not None and not uses_runtime:
        print(f'not exported: {RUNTIME_PACKAGE}: no exported package uses it')
    for name, descriptor in sorted(others.items()):
        dependents = sorted(
            m.name for m in models if name in m.get_dependencies(categories=('build', 'run')))
        needed = (f"; {', '.join(dependents)} "
                  f"{'depends' if len(dependents) == 1 else 'depend'} on it"
                  if dependents else '')
        print(f'not exported: {name} ({display_path(descriptor.path)}): a hand-written '
              f'package, not generated from a model: nothing to export, its sources are '
              f'the package{needed}')


def _positive(text):
    """Read a positive number of the command line (argparse's type)."""
    try:
        value = int(text)
    except ValueError:
        value = 0
    if value < 1:
        raise argparse.ArgumentTypeError(f"'{text}' is not a positive number")
    return value


def _runtime_files():
    """Return the files of the runtime package (our package data) to export."""
    source = runtime_source()
    files = {}
    for path in sorted(source.rglob('*')):
        relative = path.relative_to(source)
        if path.is_file() and '__pycache__' not in relative.parts:
            files[relative.as_posix()] = (
                path.read_bytes(), os.access(path, os.X_OK))
    return files


def _export_problem(export, args):
    """Return why packages cannot be exported to a folder, or None.

    An export is a source tree of ordinary ament packages: inside the
    workspace, colcon would find each package twice, as a model and as an
    exported package.
    """
    target = export.resolve()
    for base in getattr(args, 'base_paths', None) or ['.']:
        base = Path(base).resolve()
        if target == base or base in target.parents:
            return (f'{export}: error: the export folder is inside the '
                    f"workspace ('{base}'), where colcon would find every "
                    'exported package twice: choose a folder outside it')
    return None
