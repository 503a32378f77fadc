# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""The benchmarks of bench/ still run, in a tiny configuration.

Benchmarks are not tests: nothing here asserts on a time. These tests run each
benchmark's code paths on tiny workspaces and short runs, so that a change of the
generator or of the harness that breaks a benchmark shows up in CI, and check what
the benchmarks rely on (what they generate, that ratios are printed).
"""

from __future__ import annotations

from pathlib import Path
import re
import subprocess
import sys

from catkin_pkg.package import parse_package
import pytest

BENCH = Path(__file__).resolve().parent.parent / 'bench'
sys.path.insert(0, str(BENCH))

import bench_bringup  # noqa: E402
import bench_colcon  # noqa: E402
import bench_cppbuild  # noqa: E402
import bench_generation  # noqa: E402
import bench_messages  # noqa: E402
import bench_page  # noqa: E402
import bench_runtime  # noqa: E402
import bench_watch  # noqa: E402
from colcon_robmosys.check import find_model_files, load_workspace  # noqa: E402
from colcon_robmosys.check.index import InterfaceIndex  # noqa: E402
from colcon_robmosys.devtools import netns  # noqa: E402
from colcon_robmosys.generators import generate_package  # noqa: E402
from colcon_robmosys.generators import plan_package  # noqa: E402
from conftest import requires_ros  # noqa: E402
import synthetic  # noqa: E402

RATIO = r'\d+\.\d\dx'


def test_synthetic_workspace_is_valid_and_generates(tmp_path):
    shape = synthetic.write_workspace(tmp_path / 'src', 12)
    assert (shape.components, shape.service_definitions, shape.systems) == (12, 2, 2)
    phases = bench_generation.generate_workspace(tmp_path / 'src', tmp_path / 'out',
                                                 synthetic.ros_index())
    # beside the packages, as in build/: the cache of the checked models and stamps
    assert sorted(p.name for p in (tmp_path / 'out').iterdir()
                  if p.name != '.robmosys-cache') == sorted(
        [f'bench_g{g}_c{i}' for g in (0, 1) for i in range(10 if g == 0 else 2)] +
        ['bench_g0_msgs', 'bench_g1_msgs', 'bench_g0_system', 'bench_g1_system'])
    assert phases.written > 0 and phases.unchanged == 0
    # the user's implementation files were created next to the models
    assert (tmp_path / 'src' / 'bench_g1_c1' / 'src' / 'bench_g1_c1' /
            'Node1x1_impl.py').is_file()
    again = bench_generation.generate_workspace(tmp_path / 'src', tmp_path / 'out',
                                                synthetic.ros_index())
    assert (again.written, again.unchanged) == (0, phases.written)


def test_handwritten_copy_has_the_generated_packages(tmp_path):
    synthetic.write_workspace(tmp_path / 'models', 2, own_messages=False)
    assert synthetic.write_handwritten(tmp_path / 'models', tmp_path / 'hand') == 4
    for package in ('bench_g0_c0', 'bench_g0_c1', 'bench_g0_system', 'robmosys_runtime'):
        assert (tmp_path / 'hand' / package / 'package.xml').is_file()
        assert not (tmp_path / 'hand' / package / 'robmosys.yaml').exists()


def test_generation_benchmark_prints_ratios(capsys):
    assert bench_generation.main(['--sizes', '2', '4', '--repeat', '1', '--cli-size', '0']) == 0
    out = capsys.readouterr().out
    assert 'nproc' in out and 'load average at end' in out
    rows = [[cell.strip() for cell in line.split('|')[1:-1]]
            for line in out.splitlines() if re.match(r'^\| [24] ', line)]
    assert [row[0] for row in rows] == ['2', '4', '2', '4']
    # ratio to N0, and the first generation's ratio to writing its files plainly
    assert rows[0][8] == '1.00x' and re.fullmatch(RATIO, rows[1][-1])
    assert len(rows[0]) == len(rows[2]) + 2
    # the first generation against writing its files plainly, in the same run
    assert re.search(rf'plainly .* the generation takes {RATIO} the wall time, {RATIO} the CPU',
                     out)


@requires_ros
@pytest.mark.integration
def test_generation_through_the_cli_prints_its_goals():
    times = bench_generation.generation_cli.measure(3, 1, cpp_every=2)
    # the first run made the files, the copies hold them all
    assert times.files > 30 and len(times.first) == len(times.copy) == 1
    assert len(times.durable_copy) == len(times.everything) == 1
    # every file it wrote: more than the packages alone (implementation files, caches)
    assert times.written > times.files
    out = '\n'.join(bench_generation.generation_cli.report(3, times))
    # issue 28, P1: through the CLI, each goal met or not
    assert re.search(r'goal P1 no change: .* = [0-9.]+x \(goal <= 1.5x\): (met|NOT met)$', out,
                     re.MULTILINE)
    assert re.search(r'goal P1 first: .* = [0-9.]+x \(goal <= 1.5x\): (met|NOT met)$', out,
                     re.MULTILINE)
    assert re.search(r'against the durable copy .*: [0-9.]+x$', out, re.MULTILINE)
    assert re.search(r'the floor: every file .* = [0-9.]+x$', out, re.MULTILINE)


@requires_ros
@pytest.mark.integration
def test_colcon_benchmark_prints_ratios(capsys):
    assert bench_colcon.main(['--list-size', '2', '--build-size', '0', '--repeat', '1']) == 0
    out = capsys.readouterr().out
    # 4 packages of models, and robmosys_runtime
    assert re.search(rf'^\| colcon list \(2 components\) +\| 5 +\| 1 .* {RATIO} *\|$', out,
                     re.MULTILINE), out


@pytest.fixture(scope='module')
def pairs(tmp_path_factory):
    """Return a folder for the workspace of the pairs, shared by two benchmarks."""
    return str(tmp_path_factory.mktemp('pairs'))


def test_a_kept_workspace_of_the_pairs_without_cpp_is_not_taken_for_cpp(tmp_path):
    bench_runtime.write_models(tmp_path / 'src', cpp=False)
    with pytest.raises(SystemExit, match='written without C[+][+]'):
        with bench_runtime.pairs_workspace(str(tmp_path), True, 'unused-'):
            pass


@requires_ros
@pytest.mark.integration
def test_runtime_benchmark_prints_ratios(capsys, pairs):
    """The generated pair and the hand-written one both exchange messages."""
    # the latency load differs only by a burst of 1: one load is enough here
    assert bench_runtime.main(['--seconds', '0.5', '--warmup', '0.2', '--rounds', '1',
                               '--burst', '5', '--loads', 'throughput',
                               '--workspace', pairs]) == 0
    out = capsys.readouterr().out
    for kind in ('generated', 'hand-written'):
        received = re.search(rf'round 1, throughput, {kind}: (\d+) received', out)
        assert received and int(received.group(1)) >= 2, out
    pairs = 4
    if bench_runtime.cpp_skip_reason() is not None:
        assert 'C++: skipped: ' in out
    else:  # where rclcpp exists: the C++ pairs too
        pairs = 8
    assert len(re.findall(rf'^\| throughput .* {RATIO} +\|', out, re.MULTILINE)) == pairs, out


@requires_ros
@pytest.mark.integration
def test_messages_benchmark_prints_its_goals(capsys, pairs):
    """The three listeners receive, pinned; every goal is printed met or NOT met.

    C++ where rclcpp exists (not on PyPI: skipped, and the reason printed). On the
    workspace of the runtime benchmark's test, when it ran before: built again, not anew.
    """
    assert bench_messages.main(['--rounds', '1', '--seconds', '0.5', '--warmup', '0.2',
                                '--burst', '2', '--workspace', pairs]) == 0
    out = capsys.readouterr().out
    if 'skipped: needs taskset' in out:
        pytest.skip('needs taskset and two CPUs')
    goals = {'Python': 5, 'C++': 4}
    if bench_runtime.cpp_skip_reason() is not None:
        assert 'C++: skipped: rclcpp' in out
        del goals['C++']
    for title, count in goals.items():
        for kind in bench_messages.KINDS:
            received = re.findall(rf'{re.escape(title)} round 1, [^,]+, {kind}: '
                                  r'(\d+)/s received', out)
            assert len(received) == 3 and all(int(r) > 0 for r in received), out
        found = re.findall(rf'^{re.escape(title)}, .*: (met|NOT met)$', out, re.MULTILINE)
        assert len(found) == count, out


@requires_ros
def test_watch_benchmark_prints_the_cost_of_the_watch(capsys):
    """The manager's CPU with the watch on and off, and the cost against the goal."""
    assert bench_watch.main(['--sizes', '2', '--rounds', '1', '--settle', '1',
                             '--window', '1', '--timeout', '90', '--robots', '2',
                             '--robot-sizes', '4']) == 0
    out = capsys.readouterr().out
    assert len(re.findall(r'round 1, 2 instances, watch .*: \d+\.\d\d % of one CPU',
                          out)) == 2, out
    assert re.search(r'^\| 2 +\| \d+\.\d\d +\| \d+\.\d\d +\| -?\d+\.\d\d +\| '
                     r'(within|above) the goal of 50', out, re.MULTILINE), out
    assert 'reported a difference' not in out, out
    # on a site: two robots and a base station, where namespaces can be made
    if netns.unavailable_reason() is None:
        assert len(re.findall(r'round 1, 4 instances on 2 robots, watch .*: link \d+\.\d\d '
                              r'KiB/s, manager \d+\.\d\d % of one CPU', out)) == 2, out
        assert re.search(r'^\| 4 +(\| -?\d+\.\d\d +){4}\| (met|NOT met)', out,
                         re.MULTILINE), out
    else:
        assert 'hosts: not measured: ' in out, out


@requires_ros
def test_page_benchmark_prints_the_cost_of_the_page(capsys):
    """The page's own work, and the manager's CPU with the page and its clients and without."""
    assert bench_page.main(['--size', '2', '--clients', '1', '--rounds', '1', '--settle', '1',
                            '--window', '1', '--timeout', '90', '--periods', '20']) == 0
    out = capsys.readouterr().out
    assert re.search(r"^the page's work, 2 instances, 1 clients, .*: \d+\.\d{3} % of one CPU "
                     r'\((met|NOT met)', out, re.MULTILINE), out
    assert len(re.findall(r'round 1, (page|none): \d+\.\d\d % of one CPU', out)) == 2, out
    assert re.search(r'^\| 2 +(\| -?\d+\.\d\d +){3}\| (met|NOT met)', out, re.MULTILINE), out


@requires_ros
def test_modes_benchmark_prints_the_switch_against_its_steps_and_the_floor(
        test_workspace_built):
    """A switch through the manager, the same steps with rclpy, and the manager's call."""
    # in a process of its own: it sources the workspace in its environment for rclpy
    result = subprocess.run([sys.executable, str(BENCH / 'bench_modes.py'), '--install',
                             str(test_workspace_built.install), '--rounds', '2'],
                            capture_output=True, text=True, timeout=300)
    assert result.returncode == 0, result.stdout + result.stderr
    out = result.stdout
    assert re.search(r'^manager / direct: \d+\.\d\dx \(goal: at most 1\.2x\): (met|NOT met)$',
                     out, re.MULTILINE), out
    assert re.search(r'^manager / \(direct \+ two calls of the manager\): \d+\.\d\dx; '
                     r'per round, median: \d+\.\d\dx$', out, re.MULTILINE), out


@requires_ros
def test_bringup_benchmark_prints_ratios_and_counts_hangs(capsys):
    """Every system of the bring-up benchmark comes up, in both layouts, and its floor."""
    assert bench_bringup.main(['--sizes', '4', '--rounds', '1', '--hang-runs', '2',
                               '--hang-size', '2', '--timeout', '90', '--paths', 'bringup',
                               '--layouts', 'per-instance', 'shared']) == 0
    out = capsys.readouterr().out
    assert len(re.findall(r'round 1, .*: up in', out)) == 5, out
    # each Ctrl-C is timed
    assert len(re.findall(r'round 1, .*: up in .*, Ctrl-C ended it in \d+\.\d\d s', out)) == 4
    assert len(re.findall(rf'^\| 4 instances +\| (bringup|no path) +\| (per-instance|shared|'
                          rf'one, no manager \(floor\)) .* {RATIO} +\|', out,
                          re.MULTILINE)) == 3, out
    assert re.search(r'goal: 4 instances through bringup within 1.5x of the slowest single '
                     r'instance: .*: (met|NOT met)$', out, re.MULTILINE), out
    assert re.search(r'goal: the manager adds at most 1.15x to the floor, 4 instances through '
                     r'bringup: .*: (met|NOT met)$', out, re.MULTILINE), out
    assert '2 bring-ups in a row of 2 instances through bringup (shared): 2 up, 0 failed, ' \
        '0 hung' in out, out
    assert ', 0 stuck at bring-down, 0 needed SIGKILL' in out
    assert 'goal: 0 hangs in 2 bring-ups in a row through bringup: met' in out
    assert re.search(r'goal: Ctrl-C through bringup ends every process within 5 s: slowest '
                     r'\d+\.\d\d s of 6: (met|NOT met)', out), out


@requires_ros
def test_bringup_benchmark_brings_cpp_systems_up_against_their_floor(capsys):
    """With rclcpp_components and launch_ros: the C++ systems, and the floors, come up."""
    if bench_runtime.cpp_skip_reason() is not None:
        pytest.skip(bench_runtime.cpp_skip_reason())
    assert bench_bringup.main(['--sizes', '2', '--rounds', '1', '--hang-runs', '0',
                               '--timeout', '90', '--paths', 'bringup', 'launch',
                               '--cpp', '4']) == 0
    out = capsys.readouterr().out
    assert 'launch path: skipped' not in out, out
    # through each path: the C++ singles and the system of 4 in the container; the
    # floors (the one of launch started by launch), all up
    assert len(re.findall(r'round 1, .*C\+\+.*: up in', out)) == 8, out
    assert not re.search(r'round 1, .*: (failed|hung|stuck|killed)', out), out
    assert re.search(rf'^\| 2 instances +\| launch +\| one, no manager \(floor\) '
                     rf'.* {RATIO} +\|', out, re.MULTILINE), out
    assert re.search(rf'^\| 4 C\+\+ instances +\| no path +\| one, no manager \(floor\) '
                     rf'.* {RATIO} +\|', out, re.MULTILINE), out
    assert re.search(r'^4 C\+\+ instances through bringup against their floor \(no manager, '
                     rf'no container services\): {RATIO} \(medians: ', out, re.MULTILINE), out


def test_cpp_pairs_are_skipped_without_rclcpp_and_run_with_it(tmp_path):
    """What decides whether the C++ pairs are built: rclcpp & co. in a prefix."""
    reason = bench_runtime.cpp_skip_reason({})
    if reason is None:
        pytest.skip(f'{sys.prefix} itself has rclcpp, rclcpp_lifecycle and rclcpp_components')
    assert 'rclcpp, rclcpp_lifecycle, rclcpp_components not found' in reason
    index = tmp_path / 'share' / 'ament_index' / 'resource_index' / 'packages'
    index.mkdir(parents=True)
    for package in ('rclcpp', 'rclcpp_lifecycle'):
        (index / package).touch()
    reason = bench_runtime.cpp_skip_reason({'AMENT_PREFIX_PATH': str(tmp_path)})
    assert reason and reason.startswith('rclcpp_components not found'), reason
    (index / 'rclcpp_components').touch()
    assert bench_runtime.cpp_skip_reason({'CMAKE_PREFIX_PATH': str(tmp_path)}) is None


def test_cpp_pairs_are_written_to_match(tmp_path):
    """The C++ models generate, and the committed user code fits the generated classes."""
    bench_runtime.write_models(tmp_path / 'src', cpp=True)
    result = load_workspace(find_model_files([tmp_path / 'src']),
                            InterfaceIndex([Path(sys.prefix)]))
    result.raise_errors()
    for model in (bench_runtime.TALKER_CPP, bench_runtime.LISTENER_CPP):
        package, name = model['package'], model['name']
        generate_package(plan_package(result.workspace, package), tmp_path / 'out' / package)
        skeleton = (tmp_path / 'out' / package / 'src-skel' / package /
                    f'{name}_impl.hpp').read_text()
        ours = (tmp_path / 'src' / package / 'src' / package / f'{name}_impl.hpp').read_text()
        assert ours == (bench_runtime.GENERATED_CPP / f'{name}_impl.hpp').read_text()
        overrides = re.compile(r'^ +(void \w+\(.*\)) override;$', re.MULTILINE)
        assert overrides.findall(ours) == overrides.findall(skeleton) != []
    handwritten = parse_package(tmp_path / 'src' / 'bench_handwritten_cpp')
    assert handwritten.name == 'bench_handwritten_cpp'
    depends = {d.name for d in handwritten.build_depends}
    assert depends >= {'rclcpp', 'rclcpp_lifecycle', 'std_msgs'}
    cmds = bench_runtime.commands('hand-written C++', tmp_path / 'install', 1, 0.1)
    assert cmds['talker'][:2] == [str(tmp_path / 'install' / 'bench_handwritten_cpp' / 'lib' /
                                      'bench_handwritten_cpp' / 'pubsub'), 'talker']


def test_cppbuild_sides_are_written_to_match(tmp_path):
    """Both sides of the build benchmark have the same two nodes, one package each."""
    bench_cppbuild.write_generated(tmp_path / 'gen')
    bench_cppbuild.write_handwritten(tmp_path / 'hand')
    result = load_workspace(find_model_files([tmp_path / 'gen']),
                            InterfaceIndex([Path(sys.prefix)]))
    result.raise_errors()
    assert sorted(p.name for p in (tmp_path / 'gen').iterdir()) == [
        'bench_listener_cpp', 'bench_talker_cpp']
    for package, (source, cls) in bench_cppbuild.HAND.items():
        root = tmp_path / 'hand' / package
        assert parse_package(root).name == package
        # the executable comes from the library that registers the node
        registered = re.search(r'RCLCPP_COMPONENTS_REGISTER_NODE\((\S+)\)',
                               (root / 'src' / source).read_text())
        assert registered and registered.group(1) == f'bench_handwritten::{cls}'
        cmake = (root / 'CMakeLists.txt').read_text()
        assert f'PLUGIN "{registered.group(1)}"\n  EXECUTABLE {cls}\n' in cmake
        assert f'class {cls} : public rclcpp_lifecycle::LifecycleNode' in (
            root / 'src' / 'pubsub_nodes.hpp').read_text()


@pytest.mark.integration
def test_cppbuild_benchmark_prints_ratios_or_why_not(capsys):
    """With rclcpp, one clean build of each side and the ratios; without, the reason."""
    assert bench_cppbuild.main(['--rounds', '1']) == 0
    out = capsys.readouterr().out
    if bench_runtime.cpp_skip_reason() is not None:
        assert 'C++: skipped: rclcpp' in out
        return
    assert re.search(r'round 1, generated: clean colcon build in \d+\.\d s \(\d+\.\d s of CPU',
                     out), out
    assert len(re.findall(rf'^\| (clean colcon build|CPU of that build|lines of C\+\+).* '
                          rf'{RATIO} +\|', out, re.MULTILINE)) == 3, out


def test_the_cpu_of_a_process_group_is_read_to_the_nanosecond():
    """What P3 divides by: a process's own CPU time, finer than a clock tick of 10 ms."""
    busy = ('import sys, time\n'
            'end = time.process_time() + 0.25\n'
            'while time.process_time() < end:\n'
            '    pass\n'
            'print(time.process_time(), flush=True)\n'
            'sys.stdin.read()\n')
    child = subprocess.Popen([sys.executable, '-c', busy], stdin=subprocess.PIPE,
                             stdout=subprocess.PIPE, text=True, start_new_session=True)
    try:
        own = float(child.stdout.readline())
        read = bench_runtime.group_cpu_seconds(child.pid)
    finally:
        child.communicate('', timeout=30)
    # its own count, read after the line it printed: at most a few ms more
    assert own <= read < own + 0.05, (own, read)
    assert round(read * 1e9) % 10_000_000 != 0, read
