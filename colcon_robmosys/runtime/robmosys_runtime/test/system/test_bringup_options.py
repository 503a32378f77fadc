# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""bringup's options: each refuses a value out of its range in one line, exit 2."""

import pytest
from robmosys_runtime.system.bringup import apply_arguments, options
from robmosys_runtime.tools.paramcheck import RefusedFile


@pytest.mark.parametrize('option, value, said', [
    ('--timeout', '0', '--timeout 0: is not above 0'),
    ('--start-timeout', '-1', '--start-timeout -1: is not above 0'),
    ('--heartbeat', '-1', '--heartbeat -1: is below 0 (0: off)'),
    ('--respawn-delay', 'NaN', '--respawn-delay NaN: is not a number'),
    ('--diagnostics-period', '1e-9', None),
    ('--diagnostics-period', '0', '--diagnostics-period 0: is not above 0'),
    ('--check-period', '-1', '--check-period -1: is below 0 (0: off)'),
    ('--check-period', '0', None),
    ('--check-period', 'inf', '--check-period inf: is too large (at most 1e9)'),
    ('--silence', '-2', '--silence -2: is not above 0'),
    ('--check-wait', '-0.5', '--check-wait -0.5: is below 0'),
    ('--check-wait', 'ten', '--check-wait ten: is not a number'),
    ('--timeout', '1e9', None),
])
def test_a_numeric_option_refuses_a_value_out_of_its_range(capsys, option, value, said):
    parser = options('bringup.json')
    if said is None:
        assert getattr(parser.parse_args([option, value]),
                       option[2:].replace('-', '_')) == float(value)
        return
    with pytest.raises(SystemExit) as ended:
        parser.parse_args([option, value])
    assert ended.value.code == 2
    captured = capsys.readouterr()
    assert (captured.out, captured.err) == (
        '', f'bringup: error: {said}; nothing was started\n')


@pytest.mark.parametrize('value, said', [
    ('70000', '--web 70000: is not a port (0 to 65535)'),
    ('http', '--web http: is not a port (0 to 65535)'),
    ('-1', '--web -1: is not a port (0 to 65535)'),
])
def test_the_page_takes_a_port(capsys, value, said):
    parser = options('bringup.json')
    assert parser.parse_args([]).web is None
    # the launch files' default, web:='': no page
    assert parser.parse_args(['--web=']).web is None
    assert parser.parse_args(['--web', '0']).web == 0
    assert parser.parse_args([]).web_address == '127.0.0.1'
    with pytest.raises(SystemExit) as ended:
        parser.parse_args([f'--web={value}'])
    assert ended.value.code == 2
    captured = capsys.readouterr()
    assert (captured.out, captured.err) == ('', f'bringup: error: {said}; nothing was started\n')


def test_an_unknown_option_is_one_line_too(capsys):
    with pytest.raises(SystemExit):
        options('bringup.json').parse_args(['--heartbeats', '1'])
    assert capsys.readouterr().err == \
        'bringup: error: unrecognized arguments: --heartbeats 1; nothing was started\n'


DESCRIPTION = {'package': 'a_system', 'params_file': 'cfg/params.yaml', 'instances': [{
    'instance': 'laser', 'namespace': '', 'fqn': '/laser', 'remappings': [],
    'declared': [{'name': 'rate', 'type': 'double', 'origin': 'model', 'read_only': False,
                  'range': [0.0, 50.0, 0.0], 'one_of': None, 'size': None},
                 {'name': 'robmosys.component', 'type': 'string', 'origin': 'announced',
                  'read_only': True, 'range': None, 'one_of': None, 'size': None}]}]}


def test_the_operators_file_is_checked_before_anything_else(tmp_path, capsys):
    system = tmp_path / 'params.yaml'
    system.write_text('/**:\n  ros__parameters: {}\n')
    site = tmp_path / 'site.yaml'
    site.write_text('/laser:\n  ros__parameters:\n    rate: 80.0\n    rte: 1.0\n')
    args = options('bringup.json').parse_args(['--params-file', str(site)])
    with pytest.raises(RefusedFile) as refused:
        apply_arguments(DESCRIPTION, str(system), args)
    assert str(refused.value) == \
        f"--params-file '{site}' does not fit the system a_system (2 errors)"
    assert refused.value.lines == [
        f"{site}:3:11: error: parameter 'rate' of /laser: 80.0 is out of the range "
        '[0.0, 50.0]',
        f"{site}:4:5: error: node /laser has no parameter 'rte'; did you mean 'rate'? "
        '(its parameters: rate)']
    # a warning is said, and the file is used
    site.write_text('/laser:\n  ros__parameters:\n    rate: 8.0\n'
                    "    robmosys.component: 'x'\n")
    description, made = apply_arguments(DESCRIPTION, str(system), args)
    assert made != str(system)
    assert capsys.readouterr().err.splitlines() == [
        f"{site}:4:5: warning: parameter 'robmosys.component' of /laser: the node "
        'announces it of itself and never takes it from a parameter file: the value is '
        'ignored']
