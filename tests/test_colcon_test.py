# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""`colcon test` on generated packages, as ROS CI runs it after `colcon build`."""

from __future__ import annotations

from conftest import requires_ros


@requires_ros
def test_colcon_test_runs_the_generated_packages_tests(test_workspace_built):
    built = test_workspace_built
    packages = ['simple_msgs', 'publisher', 'subscriber', 'pubsub_system', 'cpp_publisher']
    result = built.colcon('test', '--packages-select', *packages,
                          '--event-handlers', 'console_cohesion+', timeout=600)
    output = result.stdout + result.stderr
    assert result.returncode == 0, output
    assert 'No task extension' not in output, output
    # the Python components' linters ran, on the generated files and the user's
    for package in ('publisher', 'subscriber'):
        results = built.build / package / 'test_results' / package
        assert {p.name for p in results.iterdir()} >= {'flake8.xunit.xml', 'pep257.xunit.xml'}
    # the results of these packages only: another test runs the tests of other
    # packages of the same build (test_bringup's smoke tests) meanwhile; a C++
    # package has none where rclcpp is not installed (colcon skips it)
    for package in [p for p in packages if (built.build / p).is_dir()]:
        summary = built.colcon('test-result', '--test-result-base', str(built.build / package),
                               '--all', '--verbose', timeout=60)
        assert summary.returncode == 0, summary.stdout + summary.stderr
        assert ' 0 errors, 0 failures' in summary.stdout, (package, summary.stdout)
