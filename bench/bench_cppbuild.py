# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""Build time: generated C++ component packages vs the same nodes written by hand.

A clean ``colcon build`` (no build, install or log folder) of the generated C++ pair of
bench_runtime.py (two component models with ``language: cpp``, their user code in
``bench/generated_cpp/``, generated and compiled by the same colcon build) against a
clean ``colcon build`` of the same two nodes written by hand, one package each, as ROS 2
documents it: one rclcpp_components library per node and its executable from
``rclcpp_components_register_node(... EXECUTABLE ... EXECUTOR MultiThreadedExecutor)``
(the nodes of ``bench/handwritten_cpp/src/pubsub_nodes.hpp``). Both sides build with the
same colcon options, alternately, in fresh folders; the fastest of the rounds counts.
It needs rclcpp, rclcpp_lifecycle and rclcpp_components (not on PyPI): with a ROS 2
install, or the prefix of ../shared/verify/, sourced. A workspace with no underlay that has
robmosys_runtime builds that package too, before its components: counted by default (what
a first workspace costs); ``--runtime-underlay`` builds it once beforehand and both sides
build on top of it (what every workspace with such an underlay costs). The line counts
compare what the
generator writes (C++ sources and CMakeLists.txt, user code aside) with the hand-written
sources and CMakeLists.txt.

    make bench-cppbuild                    # or: .venv/bin/python bench/bench_cppbuild.py
"""

from __future__ import annotations

import argparse
from pathlib import Path
import resource
import shutil
import sys
import tempfile
import time
from typing import Sequence

import yaml

from bench_runtime import (
    cpp_skip_reason, GENERATED_CPP, HANDWRITTEN_CPP, LISTENER_CPP, METADATA, TALKER_CPP)
from benchlib import best, print_end, print_machine, ratio, table
from colcon_robmosys.devtools import ros_env
from colcon_robmosys.runtime import runtime_source

#: the hand-written packages: package -> (source, node class, also the executable)
HAND = {'bench_hand_talker_cpp': ('talker.cpp', 'Talker'),
        'bench_hand_listener_cpp': ('listener.cpp', 'Listener')}

HAND_CMAKE = """cmake_minimum_required(VERSION 3.8)
project({package})

if(NOT CMAKE_CXX_STANDARD)
  set(CMAKE_CXX_STANDARD 17)
  set(CMAKE_CXX_STANDARD_REQUIRED ON)
endif()
if(CMAKE_CXX_COMPILER_ID MATCHES "GNU|Clang")
  add_compile_options(-Wall -Wextra -Wpedantic)
endif()

find_package(ament_cmake REQUIRED)
find_package(rclcpp REQUIRED)
find_package(rclcpp_components REQUIRED)
find_package(rclcpp_lifecycle REQUIRED)
find_package(std_msgs REQUIRED)

add_library(${{PROJECT_NAME}} SHARED src/{source})
target_link_libraries(${{PROJECT_NAME}} PUBLIC
  rclcpp::rclcpp
  rclcpp_components::component
  rclcpp_lifecycle::rclcpp_lifecycle
  ${{std_msgs_TARGETS}})
rclcpp_components_register_node(${{PROJECT_NAME}}
  PLUGIN "bench_handwritten::{cls}"
  EXECUTABLE {cls}
  EXECUTOR MultiThreadedExecutor)

install(TARGETS ${{PROJECT_NAME}}
  ARCHIVE DESTINATION lib
  LIBRARY DESTINATION lib
  RUNTIME DESTINATION bin)

ament_package()
"""

HAND_XML = """<?xml version="1.0"?>
<package format="3">
  <name>{package}</name>
  <version>0.1.0</version>
  <description>The hand-written {cls} of bench_cppbuild.py.</description>
  <maintainer email="bench@example.com">bench</maintainer>
  <license>Apache-2.0</license>
  <buildtool_depend>ament_cmake</buildtool_depend>
  <depend>rclcpp</depend>
  <depend>rclcpp_components</depend>
  <depend>rclcpp_lifecycle</depend>
  <depend>std_msgs</depend>
  <export>
    <build_type>ament_cmake</build_type>
  </export>
</package>
"""


def write_generated(src: Path) -> None:
    """Write the models of the generated C++ pair, with their user code."""
    for model in (TALKER_CPP, LISTENER_CPP):
        package = str(model['package'])
        (src / package).mkdir(parents=True)
        (src / package / 'robmosys.yaml').write_text(yaml.safe_dump(
            {'robmosys': 1, 'defaults': METADATA, 'components': [model]}, sort_keys=False),
            encoding='utf-8')
        code = src / package / 'src' / package
        code.mkdir(parents=True)
        for suffix in ('hpp', 'cpp'):
            name = f'{model["name"]}_impl.{suffix}'
            shutil.copyfile(GENERATED_CPP / name, code / name)


def write_handwritten(src: Path) -> None:
    """Write the hand-written packages: one library and its executable each."""
    for package, (source, cls) in HAND.items():
        (src / package / 'src').mkdir(parents=True)
        for name in (source, 'pubsub_nodes.hpp'):
            shutil.copyfile(HANDWRITTEN_CPP / 'src' / name, src / package / 'src' / name)
        (src / package / 'CMakeLists.txt').write_text(
            HAND_CMAKE.format(package=package, source=source, cls=cls), encoding='utf-8')
        (src / package / 'package.xml').write_text(
            HAND_XML.format(package=package, cls=cls), encoding='utf-8')


def _children_cpu() -> float:
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


def colcon_build(root: Path, env: dict[str, str], *args: str) -> None:
    """Run colcon build in a workspace."""
    result = ros_env.run([str(Path(sys.prefix) / 'bin' / 'colcon'), 'build', *args],
                         env=env, cwd=root, timeout=1800)
    if result.returncode:
        raise RuntimeError(f'colcon build failed in {root}:\n{result.stdout}{result.stderr}')


def runtime_underlay(root: Path, env: dict[str, str]) -> dict[str, str]:
    """Build robmosys_runtime alone into root; return env with that underlay sourced."""
    colcon_build(root, env, '--base-paths', str(runtime_source()))
    return ros_env.workspace_env(root / 'install', env)


def clean_build(root: Path, env: dict[str, str]) -> tuple[float, float]:
    """Build a workspace from scratch with colcon.

    :return: the wall-clock seconds, and the CPU seconds (user + system) of colcon
      and every process it ran (compilers, CMake), which other processes of the
      machine change much less than the wall-clock time
    """
    for folder in ('build', 'install', 'log'):
        shutil.rmtree(root / folder, ignore_errors=True)
    cpu = _children_cpu()
    start = time.perf_counter()
    colcon_build(root, env)
    return time.perf_counter() - start, _children_cpu() - cpu


def lines_of(paths: Sequence[Path]) -> int:
    """Return the number of lines of the files."""
    return sum(len(p.read_text(encoding='utf-8').splitlines()) for p in paths)


def generated_lines(root: Path) -> int:
    """Return the lines of C++ and CMake the generator wrote for the pair (build tree)."""
    files: list[Path] = []
    for model in (TALKER_CPP, LISTENER_CPP):
        package = root / 'build' / str(model['package'])
        generated = next(p for p in package.rglob('CMakeLists.txt')
                         if (p.parent / 'src-gen').is_dir())
        files += [generated, *sorted((generated.parent / 'src-gen').rglob('*.[ch]pp'))]
    return lines_of(files)


def handwritten_lines(root: Path) -> int:
    """Return the lines of the hand-written sources and CMakeLists.txt of the pair."""
    files: list[Path] = []
    for package, (source, _) in HAND.items():
        files += [root / 'src' / package / 'CMakeLists.txt', root / 'src' / package / 'src' /
                  source]
    # the nodes' header is shared by the pair: counted once
    return lines_of(files) + lines_of([HANDWRITTEN_CPP / 'src' / 'pubsub_nodes.hpp'])


def main(argv: Sequence[str] | None = None) -> int:
    """Run the benchmark and print its figures."""
    parser = argparse.ArgumentParser(description=__doc__.split('\n\n')[0])
    parser.add_argument('--rounds', type=int, default=3,
                        help='clean builds per side; the fastest counts (default: 3)')
    parser.add_argument('--runtime-underlay', action='store_true',
                        help='build robmosys_runtime once, as an underlay of both sides, '
                             'rather than in every generated build')
    args = parser.parse_args(argv)
    print_machine('build time: generated C++ component packages vs hand-written '
                  'rclcpp_components packages' +
                  (', robmosys_runtime in an underlay' if args.runtime_underlay else ''))
    skip = cpp_skip_reason()
    if skip:
        print(f'C++: skipped: {skip}')
        print_end()
        return 0
    sides = ('generated', 'hand-written')
    times: dict[str, list[float]] = {side: [] for side in sides}
    cpus: dict[str, list[float]] = {side: [] for side in sides}
    with tempfile.TemporaryDirectory(prefix='robmosys-bench-cppbuild-') as tmp:
        roots = {side: Path(tmp) / side.replace('-', '') for side in sides}
        write_generated(roots['generated'] / 'src')
        write_handwritten(roots['hand-written'] / 'src')
        env = ros_env.loopback_env(ros_env.free_domain_id())
        if args.runtime_underlay:
            (Path(tmp) / 'underlay').mkdir()
            env = runtime_underlay(Path(tmp) / 'underlay', env)
        for round_ in range(args.rounds):
            # alternate which side goes first, so that a drift of the load hits both
            for side in sides[::1 if round_ % 2 == 0 else -1]:
                seconds, cpu = clean_build(roots[side], env)
                times[side].append(seconds)
                cpus[side].append(cpu)
                print(f'  round {round_ + 1}, {side}: clean colcon build in {seconds:.1f} s '
                      f'({cpu:.1f} s of CPU)', flush=True)
        lines = (generated_lines(roots['generated']), handwritten_lines(roots['hand-written']))
    rows: list[list[object]] = []
    for label, samples in (('clean colcon build of the pair (s)', times),
                           ('CPU of that build, all processes (s)', cpus)):
        gen, hand = best(samples['generated']), best(samples['hand-written'])
        rows.append([label, f'{gen:.1f}', f'{hand:.1f}', ratio(gen, hand),
                     ' '.join(f'{t:.1f}' for t in samples['generated']),
                     ' '.join(f'{t:.1f}' for t in samples['hand-written'])])
    rows.append(['lines of C++ and CMake (user code aside)', lines[0], lines[1],
                 ratio(lines[0], lines[1]), '', ''])
    print(table(['figure', 'generated', 'hand-written', 'ratio gen/hand',
                 'generated per round', 'hand-written per round'], rows))
    print_end()
    return 0


if __name__ == '__main__':
    raise SystemExit(main())
