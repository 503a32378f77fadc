# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""
An operator's parameter file checked against a system, offline: ``ros2 run <system> check_params``.

The system's ``bringup.json`` says which nodes it has (their fully qualified
names) and which parameters each declares (``declared``: type, read-only, range,
``one_of``, size). A file's entry applies to the nodes its name matches as
rclcpp and rclpy match it: ``/*`` is one part of a name, ``/**`` any number of
them (``/**`` every node, ``/robot1/*`` the nodes right in ``/robot1``). Each
value must be one of a node it applies to: an entry naming one node must name
a parameter of that node (with a "did you mean" for a near miss); a wildcard's
value must be a parameter of at least one of its nodes, as ROS 2 leaves the
others be. A value that a node would refuse at start (its type, range and step,
``one_of``, size), or that it ignores (what a node announces of itself), is
reported at its line and column. No rclpy: it runs where the system is
installed, robot or CI.
"""

from __future__ import annotations

import argparse
import difflib
import json
import re
import sys
from typing import Any, Dict, Iterable, List, Optional, Sequence, Tuple

from robmosys_runtime.rules import ParameterRule, rule_problem
from robmosys_runtime.tools.arguments import ArgumentError
from robmosys_runtime.tools.paramfile import FileValue, NodeEntry, Problem, read_text

#: how many names a message lists at most
_LISTED = 12


def node_matches(pattern: str, fqn: str) -> bool:
    r"""
    Tell whether a file's node name applies to a node, as rclcpp and rclpy decide.

    Both turn ``/*`` into ``(/\w+)`` (so ``/**`` becomes ``(/\w+)*``) and match
    the whole fully qualified name (rclcpp's parameter_map.cpp, rclpy's node.cpp).
    """
    regex = pattern.replace('/*', r'(/\w+)')
    try:
        return re.fullmatch(regex, fqn, re.ASCII) is not None
    except re.error:
        return False


class SystemParameters:
    """The nodes of a system and what each declares, from its description (bringup.json)."""

    def __init__(self, description: Dict[str, Any], namespace: str = '') -> None:
        self.package: str = description['package']
        prefix = '/' + namespace.strip('/') if namespace.strip('/') else ''
        #: fully qualified name -> parameter name -> its description
        self.nodes: Dict[str, Dict[str, Dict[str, Any]]] = {
            prefix + i['fqn']: {d['name']: d for d in i.get('declared', ())
                                if d['origin'] != 'mapped'}
            for i in description['instances']}
        #: fully qualified name -> the templates of its mapped parameters
        self.mapped: Dict[str, List[Dict[str, Any]]] = {
            prefix + i['fqn']: [d for d in i.get('declared', ()) if d['origin'] == 'mapped']
            for i in description['instances']}

    def check(self, text: str, *, running: bool = False) -> List[Problem]:
        """
        Return what is wrong with the text of a parameter file, sorted by place.

        :param running: the file is for nodes that run already (``ros2 param
          load``): a read-only parameter cannot change there
        """
        read = read_text(text)
        problems = list(read.problems)
        nodes = self._with_arrays_of(read.entries)
        for entry in read.entries:
            problems += self._entry_problems(entry, nodes, running)
        return sorted(set(problems), key=lambda p: (p.line, p.column, p.message))

    def _with_arrays_of(self, entries: Sequence[NodeEntry]
                        ) -> Dict[str, Dict[str, Dict[str, Any]]]:
        """
        Return the nodes' parameters as a file leaves them: mapped ones by its arrays.

        A file that sets the array of a mapped parameter (its last value for a node
        wins, as the node reads its overrides) makes the node declare the parameter
        for the file's entries instead of the system's: ``joints: [a, b]`` and then
        ``a.gain`` and ``b.gain``.
        """
        arrays: Dict[str, Dict[str, List[str]]] = {}
        for entry in entries:
            for fqn, templates in self.mapped.items():
                if not templates or not node_matches(entry.name, fqn):
                    continue
                names = {t['for_each'] for t in templates}
                for value in entry.values:
                    if value.name in names and isinstance(value.value, list) and \
                            all(isinstance(v, str) for v in value.value):
                        arrays.setdefault(fqn, {})[value.name] = value.value
        if not arrays:
            return self.nodes
        nodes = dict(self.nodes)
        for fqn, values in arrays.items():
            declared = dict(nodes[fqn])
            for name in [n for n, d in declared.items() if d.get('for_each') in values]:
                del declared[name]
            for template in self.mapped[fqn]:
                if template['for_each'] not in values:
                    continue
                *groups, leaf = template['name'].split('.')
                for item in values[template['for_each']]:
                    name = '.'.join([*groups, item, leaf])
                    declared[name] = {**template, 'name': name, 'origin': 'model'}
            nodes[fqn] = declared
        return nodes

    def _entry_problems(self, entry: NodeEntry, nodes: Dict[str, Dict[str, Dict[str, Any]]],
                        running: bool) -> List[Problem]:
        matched = [fqn for fqn in nodes if node_matches(entry.name, fqn)]
        wildcard = '*' in entry.name
        if not matched:
            known = _listed(nodes)
            if wildcard:
                return [Problem(*entry.at, f'{entry.name} matches no node of the system '
                                f'{self.package!r} (its nodes: {known})')]
            return [Problem(*entry.at, f'the system {self.package!r} has no node '
                            f'{entry.name}{_did_you_mean(entry.name, nodes)} '
                            f'(its nodes: {known})')]
        problems: List[Problem] = []
        for value in entry.values:
            having: Dict[str, Dict[str, Any]] = {}
            for fqn in matched:
                declared = nodes[fqn].get(value.name)
                if declared is not None:
                    having[fqn] = declared
            if not having:
                problems.append(_unknown(nodes, entry, value, matched, wildcard))
                continue
            # one line per problem, naming every node it is a problem of
            found: Dict[Tuple[int, int, str, str], List[str]] = {}
            for fqn, declared in having.items():
                for at, severity, problem in value_problems(value, declared, running):
                    found.setdefault((*at, severity, problem), []).append(fqn)
            for (line, column, severity, problem), fqns in found.items():
                problems.append(Problem(line, column, (
                    f"parameter '{value.name}' of {', '.join(fqns)}: {problem}"), severity))
        return problems


def _unknown(nodes: Dict[str, Dict[str, Dict[str, Any]]], entry: NodeEntry, value: FileValue,
             matched: List[str], wildcard: bool) -> Problem:
    names = sorted({n for fqn in matched for n, d in nodes[fqn].items()
                    if d.get('origin') == 'model' or
                    d.get('origin') == 'node' and not d.get('read_only')})
    candidates = {n for fqn in matched for n in nodes[fqn]}
    near = _did_you_mean(value.name, candidates)
    whose = (f'no node that {entry.name} applies to ({_listed(matched)}) has a'
             if wildcard else f'node {matched[0]} has no')
    return Problem(*value.at, f"{whose} parameter '{value.name}'{near} "
                   f'(its parameters: {_listed(names)})')


def value_problems(value: FileValue, declared: Dict[str, Any], running: bool
                   ) -> List[Tuple[Tuple[int, int], str, str]]:
    """Return what is wrong with a file's value for one declared parameter: (at, severity, why)."""
    if declared.get('origin') == 'announced':
        return [(value.at, 'warning', 'the node announces it of itself and never takes '
                 'it from a parameter file: the value is ignored')]
    type_ = declared['type']
    if value.kind != type_:
        return [(value.value_at, 'error', _type_problem(value, type_))]
    problems = []
    if running and declared.get('read_only'):
        problems.append((value.at, 'error', 'read-only: a running node keeps its value '
                         '(ros2 param load cannot change it; a parameter file given at '
                         'start can)'))
    bounds = declared.get('range')
    if bounds is not None and type_ in ('int', 'double'):
        problem = range_problem(value.value, *bounds, integer=type_ == 'int')
        if problem:
            problems.append((value.value_at, 'error', problem))
    one_of, size = declared.get('one_of'), declared.get('size')
    if one_of is not None or size is not None:
        rule = ParameterRule(one_of=tuple(one_of) if one_of is not None else None,
                             size=tuple(size) if size is not None else None)
        problem = rule_problem(rule, value.value)
        if problem:
            problems.append((_element_at(value, problem), 'error', problem))
    return problems


def _element_at(value: FileValue, problem: str) -> Tuple[int, int]:
    """Return where a problem of an array's element stands: at the element."""
    if value.elements_at and problem.startswith('element '):
        for element, at in zip(value.value, value.elements_at):
            if problem.startswith(f'element {element!r} '):
                return at
    return value.value_at


def _type_problem(value: FileValue, type_: str) -> str:
    shown = repr(value.value) if value.kind == 'string' else value.text
    said = f'{shown} is read as {_article(value.kind)}, the parameter is {_article(type_)}'
    if type_ == 'byte[]':
        return said + ': rcl has no byte type, a parameter file cannot give one'
    if (value.kind, type_) in (('int', 'double'), ('int[]', 'double[]')):
        return said + ' and ROS 2 refuses one for the other: write it as a double (1.0)'
    if type_ in ('string', 'string[]'):
        return said + ': quote it to make it a string'
    return said


def range_problem(value: float, start: float, end: float, step: float, *,
                  integer: bool) -> Optional[str]:
    """Return why a number is out of a range or off its step, as ROS 2 decides it."""
    if not start <= value <= end:
        return f'{value} is out of the range [{start}, {end}]'
    if not step or value in (start, end):
        return None
    if integer:
        on_step = (value - start) % step == 0
    else:
        # rclcpp and rclpy: equal within one ulp to a step from the start
        nearest = start + round((value - start) / step) * step
        on_step = abs(value - nearest) <= sys.float_info.epsilon * abs(value + nearest)
    return None if on_step else \
        f'{value} is not on a step of {step} from {start} (range [{start}, {end}])'


def _article(type_name: str) -> str:
    return f"{'an' if type_name[0] in 'aeiou' else 'a'} {type_name}"


def _did_you_mean(name: str, candidates: Iterable[str]) -> str:
    near = difflib.get_close_matches(name, sorted(candidates), n=1, cutoff=0.6)
    return f"; did you mean '{near[0]}'?" if near else ''


def _listed(names: Iterable[str]) -> str:
    names = sorted(names)
    more = f', and {len(names) - _LISTED} more' if len(names) > _LISTED else ''
    return ', '.join(names[:_LISTED]) + more if names else 'none'


def check_files(description: Dict[str, Any], paths: Sequence[str], *, namespace: str = '',
                running: bool = False) -> List[Tuple[str, Problem]]:
    """Return the problems of parameter files checked against a system: (path, problem)."""
    system = SystemParameters(description, namespace)
    found: List[Tuple[str, Problem]] = []
    for path in paths:
        try:
            with open(path, 'rb') as stream:
                text = stream.read().decode('utf-8')
        except OSError as error:
            found.append((path, Problem(0, 0, f'cannot read it: {error.strerror}')))
            continue
        except UnicodeDecodeError as error:
            found.append((path, _not_utf8(error)))
            continue
        found += [(path, p) for p in system.check(text, running=running)]
    return found


def _not_utf8(error: UnicodeDecodeError) -> Problem:
    """Return where the first byte that is not UTF-8 stands: its line and column."""
    before = error.object[:error.start]
    start = before.rfind(b'\n') + 1
    column = len(before[start:].decode('utf-8')) + 1
    return Problem(before.count(b'\n') + 1, column,
                   f'not a text in UTF-8 (byte 0x{error.object[error.start]:02x})')


class RefusedFile(ArgumentError):
    """An operator's parameter file with errors: the message, and the line of each problem."""

    def __init__(self, message: str, lines: List[str]) -> None:
        super().__init__(message)
        #: the compiler-style line of each problem, as check_params prints them
        self.lines = lines


def check_operator_file(description: Dict[str, Any], path: str, namespace: str = '', *,
                        argument: str = 'params_file') -> List[str]:
    """
    Check an operator's parameter file before a system starts with it; return its warnings.

    What bringup (``--params-file``) and the launch files (``params_file:=``) run
    before anything starts: the check of ``check_params``, with its lines.

    :param namespace: the namespace the system is started in
    :param argument: how the caller names the file's option, for the message
    :returns: the lines of its warnings (a value the nodes ignore)
    :raises RefusedFile: when it has an error: the lines of its problems, and a
      message of one line
    """
    found = check_files(description, [path], namespace=namespace)
    lines = [line(p, problem) for p, problem in found]
    errors = sum(p.severity == 'error' for _, p in found)
    if errors:
        raise RefusedFile(
            f"{argument} {path!r} does not fit the system {description['package']} "
            f"({errors} error{'s' if errors > 1 else ''})", lines)
    return lines


def line(path: str, problem: Problem) -> str:
    """Return a problem as a compiler-style line."""
    where = f'{path}:{problem.line}:{problem.column}' if problem.line else path
    return f'{where}: {problem.severity}: {problem.message}'


def main(description_file: str, argv: Optional[Sequence[str]] = None) -> int:
    """Check parameter files against the system of a description; return the exit status."""
    parser = argparse.ArgumentParser(
        prog='check_params', description='Check ROS 2 parameter files against this '
        'system, offline: every node and parameter they name, every value they give. '
        'One compiler-style line per problem; exit 1 if there is an error.')
    parser.add_argument('files', nargs='+', metavar='FILE', help='a parameter file')
    parser.add_argument('--namespace', default='', help='the namespace the system is '
                        'launched in (the launch argument namespace:=...)')
    parser.add_argument('--running', action='store_true', help='the files are for nodes '
                        'that run (ros2 param load): read-only parameters cannot change')
    args = parser.parse_args(argv)
    with open(description_file, encoding='utf-8') as stream:
        description = json.load(stream)
    found = check_files(description, args.files, namespace=args.namespace,
                        running=args.running)
    for path, problem in found:
        print(line(path, problem), file=sys.stderr)
    errors = sum(p.severity == 'error' for _, p in found)
    if not errors:
        print(f"{', '.join(args.files)}: fits the system {description['package']}")
    return 1 if errors else 0
