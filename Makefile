# Development entry points. Needs only python3 (with venv and headers), gcc, cmake,
# make and git: ROS 2 itself comes from PyPI into .venv (see requirements/ros.txt).
#   make test   run the test suite, in TEST_JOBS=2 processes (PYTEST_ARGS='-k foo' to
#               narrow it)
#   ROS_DISTRO=jazzy (on the command line: make test ROS_DISTRO=jazzy) does the same on
#               ROS 2 Jazzy, in .venv-jazzy; Kilted is the default
#   make demo   build test_workspace with colcon and run its example system through
#               its bringup, as a user does (tools/demo.py)
#   make clean  remove the venv and the test workspace's build results
#   make bench  run the seven benchmarks of bench/ (or one: make bench-generation,
#               bench-colcon, bench-runtime, bench-bringup, bench-cppbuild, bench-watch,
#               bench-page; bench-modes, which needs make demo, runs apart;
#               BENCH_ARGS='--help' shows their options)

PYTHON ?= python3
PYTEST_ARGS ?=

# The ROS 2 distribution of the venv, from its ros-* wheels on PyPI: kilted (the
# default) or jazzy, each in a venv of its own. Only the command line chooses it: the
# ROS_DISTRO of a sourced /opt/ros/<distro> does not change which venv the tests use.
ROS_DISTRO := $(if $(filter command line,$(origin ROS_DISTRO)),$(ROS_DISTRO),kilted)
ifeq ($(ROS_DISTRO),kilted)
VENV := .venv
ROS_REQUIREMENTS := requirements/ros.txt
else ifeq ($(ROS_DISTRO),jazzy)
VENV := .venv-jazzy
ROS_REQUIREMENTS := requirements/ros-jazzy.txt
else
$(error ROS_DISTRO=$(ROS_DISTRO): the ros-* wheels on PyPI are kilted (the default) and jazzy)
endif
VPY := $(VENV)/bin/python

# The package is installed non-editable, so tests see what users get (entry points,
# templates as package data); these files decide when to reinstall it.
PKG_FILES := $(shell find colcon_robmosys templates -type f ! -name '*.pyc' 2>/dev/null) \
             $(wildcard setup.cfg setup.py)

# CI runs in a fresh clone: leave no pytest cache behind; and show where its time goes
# (a full run is to stay under 30 minutes).
ifeq ($(CI),true)
PYTEST_FLAGS := -p no:cacheprovider --durations=25
endif
# Test files run in TEST_JOBS processes (pytest-xdist), each file whole in one of them:
# much of an integration test is waiting (for DDS discovery, a timer, a timeout), and
# another file's build or nodes use that time. TEST_JOBS=1 runs them in this process.
TEST_JOBS ?= 2
ifneq ($(TEST_JOBS),1)
PYTEST_FLAGS += -n $(TEST_JOBS) --dist loadfile
endif

.PHONY: venv demo test clean bench bench-generation bench-colcon bench-runtime bench-bringup bench-cppbuild bench-watch bench-page bench-modes

venv: $(VENV)/.stamp-package

# The ROS 2 prefix: requirements, then the fix-ups the ros-* wheels need.
$(VENV)/.stamp-ros: $(ROS_REQUIREMENTS) tools/bootstrap_ros_wheels.py
	@test -x $(VPY) || $(PYTHON) -m venv $(VENV) || { \
	  echo "error: '$(PYTHON) -m venv' failed (on Debian/Ubuntu: apt-get install python3-venv)"; \
	  exit 1; }
	$(VPY) -m pip install --upgrade pip
	$(VPY) -m pip install -r $(ROS_REQUIREMENTS)
	$(VPY) tools/bootstrap_ros_wheels.py
	@touch $@

# setuptools builds in the source tree and packs whatever build/lib holds, so a
# file removed from the sources would live on in the wheel: start from nothing,
# and leave nothing behind.
SETUPTOOLS_LEFTOVERS := build/lib build/bdist.* *.egg-info
$(VENV)/.stamp-package: $(VENV)/.stamp-ros $(PKG_FILES)
	@if [ -f setup.cfg ]; then \
	  rm -rf $(SETUPTOOLS_LEFTOVERS) && \
	  $(VPY) -m pip install --no-deps --force-reinstall . && \
	  rm -rf $(SETUPTOOLS_LEFTOVERS) && { rmdir build 2>/dev/null || true; }; \
	else \
	  echo "setup.cfg is missing: colcon-robmosys is not installed into $(VENV)"; \
	fi
	@touch $@

demo: venv
	$(VPY) tools/demo.py --distro $(ROS_DISTRO)

# bin/pytest rather than 'python -m pytest': -m puts the working directory on
# sys.path, and the source tree would shadow the installed package.
test: venv
	$(VENV)/bin/pytest tests -ra $(PYTEST_FLAGS) $(PYTEST_ARGS)

# Each benchmark prints ratios measured in one run; docs/performance.md keeps the
# latest figures. bench/ is run as scripts, so the installed package is the one measured.
BENCH_ARGS ?=
bench-generation bench-colcon bench-runtime bench-bringup bench-cppbuild bench-watch bench-page: bench-%: venv
	$(VPY) bench/bench_$*.py $(BENCH_ARGS)

# a mode switch against its steps made with rclpy, on test_workspace's mode_robot_system
bench-modes: demo
	$(VPY) bench/bench_modes.py $(BENCH_ARGS)

bench: bench-generation bench-colcon bench-runtime bench-bringup bench-cppbuild bench-watch bench-page

clean:
	rm -rf $(VENV) $(SETUPTOOLS_LEFTOVERS) test_workspace/build test_workspace/install \
	  test_workspace/log test_workspace/build-$(ROS_DISTRO) test_workspace/install-$(ROS_DISTRO) \
	  test_workspace/log-$(ROS_DISTRO)
