# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

import os
from pathlib import Path
import sys


from colcon_robmosys.check.index import InterfaceIndex
from colcon_robmosys.errors import print_diagnostics
from colcon_robmosys.errors import RobmosysError
from colcon_robmosys.generators.writer import create_user_file
from colcon_robmosys.importer.interfaces import import_interfaces
from colcon_robmosys.importer.running import import_running_system
from colcon_robmosys.model import rosidl
from colcon_robmosys.model.names import package_problem
from colcon_robmosys.verb import display_path
from colcon_robmosys.verb import MAINTAINER
from colcon_robmosys.verb import SubverbVerb


class RobmosysImportVerb(SubverbVerb):
    """Write models of what already exists: interface packages, running systems.

    Each model is written once, to DIR/<package>/robmosys.yaml: an existing
    file is never replaced.
    """

    def add_arguments(self, *, parser):  # noqa: D102
        kinds = self.add_subverbs(parser, title='what to import', dest='what')
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

        graph = kinds.add_parser(
            'graph',
            help='A system model of the nodes running in the ROS graph of this '
            'domain (ROS_DOMAIN_ID), with external components for the nodes '
            'that were not generated')
        graph.add_argument(
            '--output-dir', metavar='DIR', type=Path, required=True,
            help='Write the model to DIR/<system package>/robmosys.yaml')
        graph.add_argument(
            '--system-package', metavar='NAME', default='imported_system',
            help='The package of the system model (default: imported_system)')
        graph.add_argument(
            '--namespace', metavar='NS',
            help='Import only the nodes in this namespace and below it')
        graph.add_argument(
            '--timeout', metavar='S', type=float, default=10.0,
            help='Seconds to wait for the graph to be discovered and the nodes '
            'to answer (default: 10)')
        graph.add_argument(
            '--license', default='',
            help="The system package's license (default: the one most of its "
            'components have)')
        graph.add_argument(
            '--maintainer', metavar='NAME <EMAIL>', action='append', default=[],
            help='A maintainer of the system package; repeat it for more (default: '
            'those most of its components have)')

    def main(self, *, context):  # noqa: D102
        args = context.args
        missing = self.missing_subverb(args)
        if missing:
            return missing
        try:
            rosidl.require()  # it reads interface files and checks names
        except RobmosysError as error:
            print_diagnostics(error.diagnostics)
            return 1
        if args.what == 'graph':
            return _import_graph(args)
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


def _import_graph(args) -> int:
    maintainers = [MAINTAINER.fullmatch(m) for m in args.maintainer]
    problems = [f"error: --maintainer '{m}' is not 'Name <email>'"
                for m, found in zip(args.maintainer, maintainers) if not found]
    if package_problem(args.system_package):
        problems.append(f'error: --system-package: {package_problem(args.system_package)}')
    path = args.output_dir / args.system_package / 'robmosys.yaml'
    if path.exists():
        problems.append(f'{display_path(path)}: error: the file exists: move it away to '
                        'import the system again')
    if problems:
        print('\n'.join(problems), file=sys.stderr)
        return 1
    try:
        text = import_running_system(
            args.system_package, InterfaceIndex.from_environment(),
            namespace=args.namespace, timeout=args.timeout,
            domain=os.environ.get('ROS_DOMAIN_ID', '0'), license_=args.license,
            maintainers=[{'name': found.group(1), 'email': found.group(2)}
                         for found in maintainers if found])
    except RobmosysError as error:
        print_diagnostics(error.diagnostics)
        return 1
    path.parent.mkdir(parents=True, exist_ok=True)
    if not create_user_file(path, text.encode('utf-8')):
        print(f'{display_path(path)}: error: the file exists: move it away to import the '
              'system again', file=sys.stderr)
        return 1
    print(f'imported the system {args.system_package} into {display_path(path)}')
    return 0
