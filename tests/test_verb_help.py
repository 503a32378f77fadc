# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""``colcon VERB [SUB-VERB] --help`` prints the help and exits 0, for every verb of ours.

The command lines come from the verbs' own parsers (entry points of setup.cfg, then
their sub-verbs, recursively): a new verb or sub-verb is covered without a change here.
colcon runs for real (forked warm, :mod:`harness.warm_colcon`), with colcon-defaults,
whose first parse of the command line made a required sub-verb fail ``--help``
(issue 24).
"""

from __future__ import annotations

import argparse
from collections.abc import Iterator
from importlib.metadata import entry_points
import re

import pytest

from colcon_robmosys.devtools import ros_env
from harness.warm_colcon import WarmColcon


def _subverbs(parser: argparse.ArgumentParser) -> dict[str, argparse.ArgumentParser]:
    """Return the sub-verbs of a parser by name."""
    return {name: sub for action in parser._actions
            if isinstance(action, argparse._SubParsersAction)
            for name, sub in action.choices.items()}


def _command_lines() -> dict[tuple[str, ...], argparse.ArgumentParser]:
    """Return the parser of every verb and sub-verb of ours, by its words."""
    found = {}

    def walk(words: tuple[str, ...], parser: argparse.ArgumentParser) -> None:
        found[words] = parser
        for name, sub in _subverbs(parser).items():
            walk((*words, name), sub)

    for point in entry_points(group='colcon_core.verb'):
        if point.value.startswith('colcon_robmosys.'):
            parser = argparse.ArgumentParser(prog=f'colcon {point.name}')
            point.load()().add_arguments(parser=parser)
            walk((point.name, ), parser)
    return found


COMMAND_LINES = _command_lines()


@pytest.fixture(scope='module')
def warm_colcon() -> Iterator[WarmColcon]:
    colcon = WarmColcon()
    yield colcon
    colcon.close()


def test_every_verb_and_sub_verb_is_found():
    # the walk itself: it must see the sub-verbs, or the tests below prove little
    assert ('robmosys-generate', ) in COMMAND_LINES
    assert ('robmosys-import', 'graph') in COMMAND_LINES
    assert ('robmosys-new', 'system') in COMMAND_LINES


@pytest.mark.parametrize('words', sorted(COMMAND_LINES), ids=' '.join)
def test_help_is_printed_and_exits_0(words, warm_colcon, tmp_path):
    parser = COMMAND_LINES[words]
    env = ros_env.loopback_env(ros_env.free_domain_id())
    result = warm_colcon.run([*words, '--help'], cwd=tmp_path, env=env, timeout=120)
    assert result.returncode == 0, result.stdout + result.stderr
    assert result.stderr == ''
    assert result.stdout.startswith(f"usage: colcon {' '.join(words)} "), result.stdout
    # the help of this parser: its options and its sub-verbs, each named
    for action in parser._actions:
        if action.option_strings and action.help != argparse.SUPPRESS:
            assert action.option_strings[-1] in result.stdout, action.option_strings
    for name in _subverbs(parser):
        assert re.search(rf'^    {re.escape(name)}(\s|$)', result.stdout, re.M), name
    assert not list(tmp_path.iterdir())  # help writes nothing


@pytest.mark.parametrize('words', sorted(w for w, p in COMMAND_LINES.items() if _subverbs(p)),
                         ids=' '.join)
def test_a_missing_sub_verb_is_a_usage_error(words, warm_colcon, tmp_path):
    # the sub-verb is no longer required to argparse: the verb says it is missing
    env = ros_env.loopback_env(ros_env.free_domain_id())
    result = warm_colcon.run(list(words), cwd=tmp_path, env=env, timeout=120)
    assert result.returncode == 2, result.stdout + result.stderr
    assert result.stdout == ''
    names = ','.join(_subverbs(COMMAND_LINES[words]))
    assert result.stderr.startswith(f"usage: colcon {' '.join(words)} "), result.stderr
    assert result.stderr.endswith(
        f"colcon {' '.join(words)}: error: the following arguments are required: "
        f'{{{names}}}\n'), result.stderr
