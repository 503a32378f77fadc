# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

import json
import os
from pathlib import Path
import sys

from colcon_core.package_selection import add_arguments \
    as add_packages_arguments
from colcon_core.package_selection import get_packages

from colcon_robmosys.errors import Diagnostic
from colcon_robmosys.errors import Location
from colcon_robmosys.errors import print_diagnostics
from colcon_robmosys.mapping.system import plan_system
from colcon_robmosys.package_discovery.robmosys import checked_result
from colcon_robmosys.report import report_problem
from colcon_robmosys.report import write_report
from colcon_robmosys.runtime import environ_prefixes
from colcon_robmosys.runtime import runtime_module
from colcon_robmosys.verb import add_diagnostics_arguments
from colcon_robmosys.verb import diagnostics_request
from colcon_robmosys.verb import SubverbVerb


class RobmosysCheckVerb(SubverbVerb):
    """Check files against the models of the workspace or installed systems.

    ``params``: an operator's parameter files against a system, as
    ``ros2 run <system> check_params`` checks them where the system is
    installed (the same code: robmosys_runtime.tools.paramcheck).
    """

    def add_arguments(self, *, parser):  # noqa: D102
        kinds = self.add_subverbs(parser, title='what to check', dest='what')
        params = kinds.add_parser(
            'params',
            help='ROS 2 parameter files against a system: the nodes and '
            'parameters they name, the values they give')
        params.add_argument('files', nargs='+', metavar='FILE', help='A parameter file')
        params.add_argument(
            '--system', metavar='PACKAGE', required=True,
            help='The system package: a model of the workspace, else an '
            'installed system (found in AMENT_PREFIX_PATH)')
        params.add_argument(
            '--namespace', default='',
            help='The namespace the system is launched in')
        params.add_argument(
            '--running', action='store_true',
            help='The files are for nodes that run (ros2 param load): read-only '
            'parameters cannot change')
        add_diagnostics_arguments(params)
        add_packages_arguments(params)

    def main(self, *, context):  # noqa: D102
        args = context.args
        missing = self.missing_subverb(args)
        if missing:
            return missing
        request = diagnostics_request(args)
        if request is not None and report_problem(request.path):
            print(report_problem(request.path), file=sys.stderr)
            return 1
        description, problems = _description(args)
        found = []
        if description is not None:
            paramcheck = runtime_module('tools.paramcheck')
            found = [Diagnostic(Location(path, problem.line, problem.column),
                                problem.message, problem.severity)
                     for path, problem in paramcheck.check_files(
                         description, args.files, namespace=args.namespace,
                         running=args.running)]
        print_diagnostics(problems + found)
        if request is not None:
            try:
                write_report(request, args.files, problems + found)
            except OSError as error:
                print(f'{request.path}: error: cannot write the report: '
                      f'{error.strerror}', file=sys.stderr)
                return 1
        if problems or any(d.severity == 'error' for d in found):
            return 1
        print(f"{', '.join(args.files)}: fits the system {args.system}")
        return 0


def _description(args):
    """Return the description of the system (bringup.json's), and the problems of its model.

    A system of the workspace is described from its model, as its build
    would install it; else the installed one is read.
    """
    for decorator in get_packages(args):
        descriptor = decorator.descriptor
        if descriptor.name != args.system or descriptor.type != 'robmosys.system':
            continue
        result = checked_result(descriptor)
        model_file = descriptor.metadata['robmosys_model_file']
        errors = [e for e in result.errors if e.location.path == model_file]
        if errors or model_file in result.broken_files:
            return None, errors or [Diagnostic(
                Location(model_file), f'the system {args.system} cannot be checked '
                'against: its model has errors')]
        system = result.workspace.model(args.system)
        return json.loads(plan_system(system, result.workspace).bringup_description), []
    for prefix in environ_prefixes(os.environ, 'AMENT_PREFIX_PATH'):
        path = Path(prefix) / 'share' / args.system / 'bringup.json'
        if path.is_file():
            with path.open(encoding='utf-8') as stream:
                return json.load(stream), []
    return None, [Diagnostic(Location(args.system), (
        'no system of this name: neither a system model of the workspace nor an '
        'installed system package (share/<package>/bringup.json in AMENT_PREFIX_PATH)'))]
