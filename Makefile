# vwg — the two entry points on a fresh Debian 12 machine (as root, or a user with sudo):
#   make demo    install what is missing, build, and run the main example
#   make test    install what is missing, build, and run every test (Python, C++ with sanitizers,
#                the installed C++ package through a downstream project)
# Other targets: install, bench, stubs, lint, cpp-test, cpp-package, clean.

SHELL := /bin/bash
.SHELLFLAGS := -eu -o pipefail -c
.DEFAULT_GOAL := help

PYTHON ?= python3
VENV ?= .venv
PY := $(VENV)/bin/python
PIP := $(VENV)/bin/pip
JOBS ?= $(shell nproc)
SUDO := $(shell [ "$$(id -u)" = 0 ] || echo sudo)

# Debian packages: compilers and tools, then the libraries of DESIGN.md.
APT_PACKAGES := build-essential cmake pkg-config python3-dev python3-venv \
	libeigen3-dev libbox2d-dev libompl-dev libapriltag-dev \
	libopencv-core-dev libopencv-imgproc-dev libopencv-imgcodecs-dev libopencv-videoio-dev libopencv-calib3d-dev \
	libboost-serialization-dev libboost-filesystem-dev libboost-system-dev \
	libgtest-dev ffmpeg

BUILD := build
STAMP := $(BUILD)/stamps

.PHONY: help deps venv install demo test pytest lint stubs cpp-test cpp-package bench clean

help:
	@sed -n '1,7p' Makefile | sed 's/^# \{0,1\}//'

$(STAMP):
	@mkdir -p $(STAMP)

## Debian packages, installed only when missing.
deps:
	@missing=""; for p in $(APT_PACKAGES); do \
	  dpkg-query -W -f='$${Status}' $$p 2>/dev/null | grep -q "ok installed" || missing="$$missing $$p"; \
	done; \
	if [ -n "$$missing" ]; then \
	  echo "apt-get install:$$missing"; \
	  $(SUDO) apt-get update -qq; \
	  DEBIAN_FRONTEND=noninteractive $(SUDO) apt-get install -y -qq --no-install-recommends $$missing; \
	else echo "Debian packages: all present"; fi

$(VENV)/bin/python:
	$(PYTHON) -m venv $(VENV)
	$(PIP) install -q --upgrade pip

venv: $(VENV)/bin/python

## The Python package with its test tools (the C++ core is built by scikit-build-core).
install: deps venv
	$(PIP) install -q ".[test]"
	@$(PY) -c "import vwg; print('vwg', vwg.__version__, 'installed in $(VENV)')"

## The main job: the robot case study on the office world (A* to the kitchen), its frame log
## replayed, and the map in 3D.
demo: install
	@mkdir -p out
	$(VENV)/bin/vwg run maps/office.yaml --planner astar --goal kitchen --no-world-orders \
		--video out/office_kitchen.mp4 --summary-json out/office_kitchen.json --record out/office_kitchen.jsonl
	$(VENV)/bin/vwg replay out/office_kitchen.jsonl
	$(VENV)/bin/vwg overview maps/office.yaml -o out/office_3d.png
	@echo
	@echo "Outputs in out/:"
	@echo "  office_kitchen.mp4    the run from above (H.264; any browser plays it)"
	@echo "  office_kitchen.png    the trajectories"
	@echo "  office_kitchen.json   the summary (reached, frames, path length, collisions, replans)"
	@echo "  office_kitchen.jsonl  the frame log (one line per frame; vwg replay checks it)"
	@echo "  office_3d.png         the office in 3D"

test: install lint pytest cpp-test cpp-package
	@echo "make test: all passed"

pytest:
	$(PY) -m pytest -q

lint:
	$(VENV)/bin/ruff check python tests examples benchmarks

## Stubs of the compiled module (tests/test_stubs.py fails when they drift from the module).
stubs:
	$(PY) tools/make_stubs.py

## C++ unit tests with AddressSanitizer and UndefinedBehaviorSanitizer, warnings as errors.
cpp-test: deps
	cmake -S . -B $(BUILD)/cpp-asan -DCMAKE_BUILD_TYPE=Debug -DVWG_TESTS=ON -DVWG_SANITIZE=ON -DVWG_WERROR=ON > /dev/null
	cmake --build $(BUILD)/cpp-asan -j $(JOBS)
	cd $(BUILD)/cpp-asan && ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1 ctest --output-on-failure -j $(JOBS)

## Install the C++ package, then build and run the downstream project examples/cpp against it.
cpp-package: deps
	cmake -S . -B $(BUILD)/cpp-release -DCMAKE_BUILD_TYPE=Release -DCMAKE_INSTALL_PREFIX=$(CURDIR)/$(BUILD)/prefix > /dev/null
	cmake --build $(BUILD)/cpp-release -j $(JOBS) --target vwg_core
	cmake --install $(BUILD)/cpp-release > /dev/null
	cmake -S examples/cpp -B $(BUILD)/example-cpp -DCMAKE_PREFIX_PATH=$(CURDIR)/$(BUILD)/prefix > /dev/null
	cmake --build $(BUILD)/example-cpp -j $(JOBS)
	cd $(BUILD)/example-cpp && ctest --output-on-failure

bench: install
	@for b in benchmarks/bench_*.py; do echo "== $$b"; $(PY) $$b; done

clean:
	rm -rf $(BUILD) out
