# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

from pathlib import Path
import subprocess
import sys

from colcon_core.package_discovery import add_package_discovery_arguments
from colcon_core.package_discovery import discover_packages
from colcon_core.package_identification import \
    get_package_identification_extensions

from colcon_robmosys.check import load_workspace
from colcon_robmosys.generators.starter import Maintainer
from colcon_robmosys.generators.starter import name_problems
from colcon_robmosys.generators.starter import render_starter
from colcon_robmosys.generators.starter import starter_component
from colcon_robmosys.generators.starter import starter_system
from colcon_robmosys.generators.starter import StarterDefinition
from colcon_robmosys.generators.starter import StarterInfo
from colcon_robmosys.generators.writer import create_user_file
from colcon_robmosys.model.names import package_problem
from colcon_robmosys.model.types import Component
from colcon_robmosys.model.types import Language
from colcon_robmosys.package_discovery.robmosys import METADATA_KEY
from colcon_robmosys.verb import display_path
from colcon_robmosys.verb import MAINTAINER
from colcon_robmosys.verb import SubverbVerb

#: what the kinds say in the help and in what the verb prints
KINDS = {
    'definition': 'a service definition: messages and services of an interface package',
    'component': 'a component: a lifecycle node in C++ or Python',
    'system': 'a system: instances of components, connected',
}


class RobmosysNewVerb(SubverbVerb):
    """Write a commented starting model: a service definition, a component, a system.

    The model goes to DIR/NAME/robmosys.yaml, valid and ready to build; an
    existing file is never replaced.
    """

    def add_arguments(self, *, parser):  # noqa: D102
        kinds = self.add_subverbs(parser, title='the kind of model', dest='kind')
        for kind, help_ in KINDS.items():
            sub = kinds.add_parser(kind, help=help_)
            sub.add_argument(
                'name', metavar='NAME',
                help='The package the model becomes (a ROS 2 package name); the '
                'model is written to DIR/NAME/robmosys.yaml')
            sub.add_argument(
                '--path', metavar='DIR', type=Path, default=Path('.'),
                help='The folder to write DIR/NAME/robmosys.yaml in (default: '
                'the current folder; in a workspace, src)')
            sub.add_argument(
                '--license', default='Apache-2.0',
                help='The license of the package (default: Apache-2.0)')
            sub.add_argument(
                '--maintainer', metavar='NAME <EMAIL>', action='append', default=[],
                help="A maintainer of the package, 'Name <email>'; repeat it for "
                "more (default: git's user.name and user.email)")
            if kind == 'component':
                sub.add_argument(
                    '--language', choices=[lang.value for lang in Language],
                    default='python', help='The language of the node (default: python)')
                sub.add_argument(
                    '--interfaces', metavar='PACKAGE',
                    help='Exchange the message Sample of this service definition, '
                    "written by 'colcon robmosys-new definition PACKAGE' (default: "
                    'std_msgs/msg/String)')
            if kind == 'system':
                sub.add_argument(
                    '--components', metavar='PACKAGE', nargs='+', required=True,
                    help='The components to instance, each once, by package: of '
                    'the workspace (found as colcon finds packages) or of its '
                    'underlays; ports that fit are connected')
                sub.add_argument(
                    '--modes', action='store_true',
                    help="Start with two modes: 'running' (every managed instance "
                    "active) and 'idle' (none), 'running' first")
                add_package_discovery_arguments(sub)

    def main(self, *, context):  # noqa: D102
        args = context.args
        missing = self.missing_subverb(args)
        if missing:
            return missing
        problems = [f'error: {p}' for p in name_problems(args.kind, args.name)]
        maintainers, problem = _maintainers(args.maintainer)
        if problem:
            problems.append(problem)
        interfaces = getattr(args, 'interfaces', None)
        if interfaces is not None and package_problem(interfaces):
            problems.append(f"error: --interfaces: '{interfaces}' "
                            f'{package_problem(interfaces)}')
        path = args.path / args.name / 'robmosys.yaml'
        if path.exists() or path.is_symlink():
            problems.append(f'{display_path(path)}: error: the file exists: it is '
                            'not replaced (remove it, or choose another NAME or --path)')
        if problems:
            print('\n'.join(problems), file=sys.stderr)
            return 1
        info = StarterInfo(args.name, args.license, tuple(maintainers))
        if args.kind == 'definition':
            starter = StarterDefinition(info)
        elif args.kind == 'component':
            starter = starter_component(info, Language(args.language), interfaces)
        else:
            components, problem = _components(args)
            if problem:
                print(problem, file=sys.stderr)
                return 1
            starter = starter_system(info, components, modes=args.modes)
        path.parent.mkdir(parents=True, exist_ok=True)
        if not create_user_file(path, render_starter(starter).encode('utf-8')):
            print(f'{display_path(path)}: error: the file exists: it is not replaced',
                  file=sys.stderr)
            return 1
        print(f'created {display_path(path)}: {KINDS[args.kind].split(":")[0]} '
              f"'{args.name}', yours to edit; check it with 'colcon "
              f"robmosys-generate --validate-only'")
        return 0


def _maintainers(given):
    """Return the maintainers of the command line, or of git's configuration."""
    found = [MAINTAINER.fullmatch(m) for m in given]
    bad = [m for m, match in zip(given, found) if not match]
    if bad:
        return [], f"error: --maintainer '{bad[0]}' is not 'Name <email>'"
    if given:
        return [Maintainer(m.group(1), m.group(2)) for m in found], None
    name, email = _git_config('user.name'), _git_config('user.email')
    match = MAINTAINER.fullmatch(f'{name} <{email}>') if name and email else None
    if match is None:
        return [], ("error: who maintains the package? Give --maintainer 'Name "
                    "<email>' (or set git config user.name and user.email)")
    return [Maintainer(match.group(1), match.group(2))], None


def _git_config(key):
    """Return a value of git's configuration, or None."""
    try:
        result = subprocess.run(['git', 'config', '--get', key], capture_output=True,
                                text=True, timeout=10, check=False)
    except (OSError, subprocess.SubprocessError):
        return None
    return result.stdout.strip() or None if result.returncode == 0 else None


def _components(args):
    """Return the component models a system instances, or why not."""
    descriptors = discover_packages(args, get_package_identification_extensions())
    ours = [d for d in descriptors if METADATA_KEY in d.metadata]
    # a workspace without models of its own still has its underlays'
    result = ours[0].metadata[METADATA_KEY].result if ours else load_workspace([])
    known = {m.package: m for m in result.workspace.models if isinstance(m, Component)}
    missing = [c for c in args.components if c not in known]
    if missing:
        return [], (f"error: --components: {', '.join(repr(m) for m in missing)}: no "
                    'component of the workspace or of its underlays (known: '
                    f"{', '.join(sorted(known)) or 'none'})")
    return [known[c] for c in args.components], None
