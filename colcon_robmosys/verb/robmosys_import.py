# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

from pathlib import Path
import sys

from colcon_core.plugin_system import satisfies_version
from colcon_core.verb import VerbExtensionPoint

from colcon_robmosys.check.index import InterfaceIndex
from colcon_robmosys.errors import print_diagnostics
from colcon_robmosys.errors import RobmosysError
from colcon_robmosys.generators.writer import create_user_file
from colcon_robmosys.importer.interfaces import import_interfaces
from colcon_robmosys.verb import display_path


class RobmosysImportVerb(VerbExtensionPoint):
    """Write models of what already exists: installed interface packages.

    Each model is written once, to DIR/<package>/robmosys.yaml: an existing
    file is never replaced.
    """

    def __init__(self):  # noqa: D107
        super().__init__()
        satisfies_version(VerbExtensionPoint.EXTENSION_POINT_VERSION, '^1.0')

    def add_arguments(self, *, parser):  # noqa: D102
        kinds = parser.add_subparsers(
            title='what to import', dest='what', metavar='{interfaces}')
        kinds.required = True
        interfaces = kinds.add_parser(
            'interfaces',
            help='Service definitions of installed interface packages '
            '(found in AMENT_PREFIX_PATH)')
        interfaces.add_argument(
            'packages', nargs='+', metavar='PACKAGE',
            help='The interface packages to import')
        interfaces.add_argument(
            '--output-dir', metavar='DIR', type=Path, required=True,
            help='Write the model of each package to DIR/<package>/robmosys.yaml')
        interfaces.add_argument(
            '--redeclare', action='store_true',
            help='Write models that generate the packages again, for a team '
            'that owns and evolves them (by default the models describe the '
            'installed packages, external: true, and generate nothing)')

    def main(self, *, context):  # noqa: D102
        args = context.args
        try:
            models = import_interfaces(
                list(dict.fromkeys(args.packages)), InterfaceIndex.from_environment(),
                redeclare=args.redeclare)
        except RobmosysError as error:
            print_diagnostics(error.diagnostics)
            return 1
        status = 0
        for model in models:
            path = args.output_dir / model.package / 'robmosys.yaml'
            path.parent.mkdir(parents=True, exist_ok=True)
            if not create_user_file(path, model.text().encode('utf-8')):
                print(f'{display_path(path)}: error: the file exists: move it away to '
                      'import the package again', file=sys.stderr)
                status = 1
                continue
            print(f'imported {model.package} into {display_path(path)}')
        return status
