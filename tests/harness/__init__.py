"""Helpers shared by the tests: the ROS 2 environment, processes with timeouts."""
