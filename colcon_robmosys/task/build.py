# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

import argparse
import os
from pathlib import Path

from colcon_core.event.output import StderrLine
from colcon_core.logging import colcon_logger
from colcon_core.plugin_system import satisfies_version
from colcon_core.task import TaskExtensionPoint
from colcon_ros.task.ament_cmake.build import AmentCmakeBuildTask

from colcon_robmosys.check.cache import CACHE_DIR
from colcon_robmosys.errors import print_diagnostics
from colcon_robmosys.errors import RobmosysError
from colcon_robmosys.generators import fingerprint
from colcon_robmosys.generators import generate_package
from colcon_robmosys.generators import plan_package
from colcon_robmosys.generators import StampStore
from colcon_robmosys.generators import unchanged_package
from colcon_robmosys.mapping.distributions import distribution_problem
from colcon_robmosys.package_discovery.robmosys import checked_result
from colcon_robmosys.report import report_problem
from colcon_robmosys.report import ReportRequest
from colcon_robmosys.report import write_report

logger = colcon_logger.getChild(__name__)

#: whether a build of this process has reported the shell's unsupported ROS 2
#: distribution (colcon runs the packages' tasks in one process)
_distribution_reported = False

#: The folder, inside the package's build folder, of the generated sources.
GENERATED_DIR = 'src-gen'
#: The JUnit report of a package's model, where ament puts the results of its
#: tests (in build/<package>/): `colcon test-result` collects it with them.
TEST_RESULT = Path('test_results') / '{package}' / 'robmosys_model.xml'


class RobmosysBuildTask(TaskExtensionPoint):
    """Generate a package from its model, then build it the ament way."""

    def __init__(self):  # noqa: D107
        super().__init__()
        satisfies_version(TaskExtensionPoint.EXTENSION_POINT_VERSION, '^1.0')

    def add_arguments(self, *, parser):  # noqa: D102
        try:
            parser.add_argument(
                '--robmosys-test-results', action='store_true',
                help='Write the diagnostics of the model of each RobMoSys '
                'package, warnings included, as JUnit XML to build/<package>/'
                f"{TEST_RESULT.as_posix().format(package='<package>')}, where "
                "'colcon test-result' collects them, even for a package whose "
                'model has errors')
        except argparse.ArgumentError:
            # the four package types share this task: the first adds it
            pass

    async def build(self):  # noqa: D102
        pkg, args = self.context.pkg, self.context.args
        result = checked_result(pkg)
        model_file = pkg.metadata['robmosys_model_file']
        errors = result.errors_of(model_file)
        _test_result(args, pkg.name, model_file,
                     errors + result.warnings_of(pkg.name))
        problem = distribution_problem(os.environ)
        if problem:
            # before anything is generated: the packages could not build
            # here. The error once, as for a model's; each package says what
            # it holds back
            global _distribution_reported
            line = f"cannot generate '{pkg.name}': see the error on ROS_DISTRO\n"
            if not _distribution_reported:
                _distribution_reported = True
                line = f'error: {problem}\n' + line
            self.context.put_event_into_queue(StderrLine(line.encode()))
            return 1
        if errors or model_file in result.broken_files:
            # discovery has printed them; this package's failure in colcon's
            # summary says what it holds back
            print_diagnostics(errors)
            self.context.put_event_into_queue(StderrLine(
                f"cannot generate '{pkg.name}': {model_file} has errors\n"
                .encode()))
            return 1
        # warnings go with the package's own output, like a compiler's: in
        # its build log, on the console, in colcon's summary of packages
        # with stderr output; they stop nothing
        for diagnostic in result.warnings_of(pkg.name):
            self.context.put_event_into_queue(
                StderrLine(f'{diagnostic}\n'.encode()))
        source_dir = Path(args.build_base) / GENERATED_DIR
        # args.build_base is build/<package>: the stamps are kept beside the
        # cache of the checked models, in build/
        stamps = StampStore(Path(args.build_base).parent / CACHE_DIR / 'stamps')
        inputs = fingerprint(result, pkg.name, standalone=False)
        try:
            # an unchanged package is not even planned
            report = unchanged_package(source_dir, stamps, inputs) or \
                generate_package(plan_package(result.workspace, pkg.name), source_dir,
                                 stamps=stamps, fingerprint=inputs, standalone=False)
        except RobmosysError as error:
            print_diagnostics(error.diagnostics)
            return 1
        logger.info(
            f"Generated '{pkg.name}' in '{source_dir}': "
            f'{len(report.written)} files written, '
            f'{len(report.unchanged)} unchanged, '
            f'{len(report.removed)} removed')

        # the generated tree is an ordinary ament_cmake package; the user's
        # files are built and installed where they live, next to the model,
        # so that compilers, debuggers, linters and symlinks point there
        args.path = str(source_dir)
        # where the model file is: the package installs beside the copy of its model
        # where it was built from, so that the system manager's reports name the
        # file the user wrote (common/installed_model.cmake.jinja)
        cmake_args = [f'-DROBMOSYS_MODEL_FILE={os.path.abspath(model_file)}']
        if pkg.type == 'robmosys.component':
            # only components have files of the user's: CMake warns of a variable
            # that a package does not use
            cmake_args.append(
                f'-DROBMOSYS_SOURCE_DIR={os.path.abspath(Path(model_file).parent)}')
        args.cmake_args = list(getattr(args, 'cmake_args', None) or []) + cmake_args
        extension = AmentCmakeBuildTask()
        extension.set_context(context=self.context)
        return await extension.build()


def _test_result(args, package, model_file, diagnostics):
    """Write the JUnit report of a package's model, or remove the last one.

    A report left by an earlier build asked for it would tell what is no
    longer true; only a report of ours is removed.
    """
    path = Path(args.build_base) / str(TEST_RESULT).format(package=package)
    if not getattr(args, 'robmosys_test_results', False):
        if path.is_file() and report_problem(path) is None:
            path.unlink()
        return
    problem = report_problem(path)
    if problem:
        logger.warning(problem)
        return
    write_report(ReportRequest('junit', path), [model_file], diagnostics)
