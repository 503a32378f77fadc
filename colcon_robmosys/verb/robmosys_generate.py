# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

import os
from pathlib import Path
import sys

from colcon_core.package_selection import add_arguments \
    as add_packages_arguments
from colcon_core.package_selection import get_packages
from colcon_core.plugin_system import satisfies_version
from colcon_core.verb import VerbExtensionPoint

from colcon_robmosys.errors import print_diagnostics
from colcon_robmosys.errors import RobmosysError
from colcon_robmosys.generators import create_missing_user_files
from colcon_robmosys.generators import generate_package
from colcon_robmosys.generators import plan_package
from colcon_robmosys.package_discovery.robmosys import checked_result


class RobmosysGenerateVerb(VerbExtensionPoint):
    """Generate ROS 2 packages from RobMoSys models, without building.

    Creates the implementation files a model asks for and that do not exist
    yet, next to the model; existing files are never touched.
    """

    def __init__(self):  # noqa: D107
        super().__init__()
        satisfies_version(VerbExtensionPoint.EXTENSION_POINT_VERSION, '^1.0')

    def add_arguments(self, *, parser):  # noqa: D102
        parser.add_argument(
            '--output-dir', metavar='DIR', type=Path,
            help='Write the generated packages to DIR/<package> (by default '
            'nothing but the missing implementation files is written)')
        parser.add_argument(
            '--validate-only', action='store_true',
            help='Check the models and write nothing; exit non-zero on errors')
        add_packages_arguments(parser)

    def main(self, *, context):  # noqa: D102
        args = context.args
        decorators = get_packages(args)
        selected = [
            d.descriptor for d in decorators
            if d.selected and d.descriptor.type.startswith('robmosys.')]
        if not selected:
            print('No RobMoSys model selected', file=sys.stderr)
            return 0
        result = checked_result(selected[0])
        print_diagnostics(
            w for d in selected for w in result.warnings_of(d.name))
        model_files = {d.metadata['robmosys_model_file'] for d in selected}
        errors = [e for e in result.errors
                  if e.location.path in model_files]
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
        status = 0
        if args.output_dir is not None:
            # as colcon marks build/ and install/: the generated packages
            # must not be found as packages of the workspace next time
            args.output_dir.mkdir(parents=True, exist_ok=True)
            marker = args.output_dir / 'COLCON_IGNORE'
            if not marker.exists():
                # created once: touching it would change its mtime on
                # every run, and a run with no change changes nothing
                marker.touch()
        for descriptor in selected:
            try:
                plan = plan_package(result.workspace, descriptor.name)
                for path in create_missing_user_files(plan):
                    print(f'created {_display(path)}: yours to fill in')
                if args.output_dir is not None:
                    out = args.output_dir / descriptor.name
                    # output the user keeps (it may be under version
                    # control), unlike the build tree: made durable
                    report = generate_package(plan, out, sync=True)
                    print(f'generated {descriptor.name} in {_display(out)}: '
                          f'{len(report.written)} written, '
                          f'{len(report.unchanged)} unchanged, '
                          f'{len(report.removed)} removed')
            except RobmosysError as error:
                print_diagnostics(error.diagnostics)
                status = 1
        return status


def _display(path):
    try:
        return os.path.relpath(path)
    except ValueError:
        return str(path)
