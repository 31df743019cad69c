# sph_fsi: build, run and test from a local virtual environment.
#   make run       create .venv, install everything pinned and compile the main job's kernels into Numba's cache
#                  (once, `sph-fsi compile`: about 2 minutes on a fresh clone), then run the ROS 2 node on the
#                  paper's elastic gate at the paper's 1 mm with the default scheme (about a minute on 2 cores; a
#                  progress line every 10 s), recording MCAP + Rerun into runs/, its summary and time series into
#                  runs/elastic_gate/, and exit at the end: about 4-5 minutes in all on a fresh clone.
#                  A quick look: make run NODE_PARAMS="-p numerics.spacing:=0.002 -p solid.scheme:=gray2001"
#   make headless  the same install, then `sph-fsi run` (no ROS) on SCENE into OUT
#   make test      same install, then the test suite (about 12 minutes on a clean clone with 2 cores)
#   make test-fast same install, then the suite without the tests marked slow (`-m "not slow"`: no validation
#                  runs, long physics runs or long node runs): the everyday loop
# Measured times, with their dates: docs/performance/BENCH.md, "A fresh clone".
# Variables: VENV; for run: NODE_SCENE, NODE_PARAMS (extra `-p key:=value`); for headless: SCENE (scene name or
# YAML file; empty = default scene), OUT, ARGS (extra CLI arguments).

SHELL := /bin/bash

PYTHON ?= python3
VENV ?= .venv
PY = $(VENV)/bin/python

SCENE ?=
SCENE_NAME = $(if $(SCENE),$(basename $(notdir $(SCENE))),default)
OUT ?= runs/$(SCENE_NAME)
ARGS ?=
PYTEST_ARGS ?=
# The suite runs one test file per worker (pytest-xdist), each single-threaded: most tests are small serial runs,
# so two workers use both cores where one worker with two Numba threads kept one busy.
TEST_WORKERS ?= 2
TEST_THREADS ?= 1

STAMP = $(VENV)/.installed
# The editable install maps the packages that exist when it runs: reinstall when a package appears.
PKG_INITS = $(wildcard sph_fsi/__init__.py sph_fsi_core/__init__.py sph_fsi_core/*/__init__.py)

.PHONY: all install run headless test test-fast validate stability bench clean distclean

all: install

$(STAMP): requirements.txt requirements-dev.txt setup.py setup.cfg package.xml $(PKG_INITS)
	test -x $(PY) || $(PYTHON) -m venv $(VENV)
	$(PY) -m pip install --upgrade pip
	$(PY) -m pip install -r requirements-dev.txt
	$(PY) -m pip install -e . --no-deps
	$(PY) -m sph_fsi.cli compile $(NODE_SCENE) || echo "make: compiling ahead did not finish; runs compile what they need"
	touch $@

install: $(STAMP)

NODE_SCENE ?= elastic_gate
NODE_PARAMS ?=

run: install
	mkdir -p runs
	$(VENV)/bin/sph_fsi_node --ros-args -p scene:=$(NODE_SCENE) $(NODE_PARAMS) -p on_end:=exit \
	    -p mcap_path:=runs/$(NODE_SCENE).mcap -p rrd_path:=runs/$(NODE_SCENE).rrd -p out_dir:=runs/$(NODE_SCENE)
	@echo "Run:        runs/$(NODE_SCENE)/summary.json (checks or error against the reference, wall time), timeseries.csv"
	@echo "Recordings: runs/$(NODE_SCENE).mcap (Foxglove: open the file; rosbags / mcap-ros2-support in Python)"
	@echo "            runs/$(NODE_SCENE).rrd  (Rerun viewer: $(VENV)/bin/rerun runs/$(NODE_SCENE).rrd)"

headless: install
	$(PY) -m sph_fsi.cli run $(SCENE) --out $(OUT) $(ARGS)
	@echo "Outputs in $(OUT)/ (timeseries.csv, summary.json, snapshots)"

# Tests get their own ROS domains (a random base 1..100; the node test files take fixed offsets from it) and stay
# on this host. test-fast: the same, without the tests marked `slow` (test/conftest.py registers the marker).
TEST_ENV = export ROS_AUTOMATIC_DISCOVERY_RANGE=LOCALHOST; \
	export ROS_DOMAIN_ID=$$(( RANDOM % 100 + 1 )); \
	export NUMBA_NUM_THREADS=$(TEST_THREADS); \
	echo "ROS_DOMAIN_ID=$$ROS_DOMAIN_ID, $(TEST_WORKERS) pytest workers x $(TEST_THREADS) Numba thread(s)"
PYTEST = $(PY) -m pytest -q -p no:cacheprovider -n $(TEST_WORKERS) --dist loadfile

test: install
	$(TEST_ENV); $(PYTEST) $(PYTEST_ARGS) test

test-fast: install
	$(TEST_ENV); $(PYTEST) -m "not slow" $(PYTEST_ARGS) test

validate: install
	$(PY) -m sph_fsi.cli validate $(ARGS)

stability: install
	$(PY) -m sph_fsi.cli stability $(ARGS)

bench: install
	$(PY) -m bench.run_all $(ARGS)

clean:
	rm -rf runs
	find . -path ./$(VENV) -prune -o -type d -name __pycache__ -prune -exec rm -rf {} +

distclean: clean
	rm -rf $(VENV) *.egg-info
