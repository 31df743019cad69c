# sph_fsi: build, run and test from a local virtual environment.
#   make run    create .venv, install everything pinned, run the default scene
#   make test   same install, then the test suite
# Variables: VENV, SCENE (scene name or YAML file; empty = default scene), OUT, ARGS (extra CLI arguments).

SHELL := /bin/bash

PYTHON ?= python3
VENV ?= .venv
PY = $(VENV)/bin/python

SCENE ?=
SCENE_NAME = $(if $(SCENE),$(basename $(notdir $(SCENE))),default)
OUT ?= runs/$(SCENE_NAME)
ARGS ?=
PYTEST_ARGS ?=

STAMP = $(VENV)/.installed
# The editable install maps the packages that exist when it runs: reinstall when a package appears.
PKG_INITS = $(wildcard sph_fsi/__init__.py sph_fsi_core/__init__.py sph_fsi_core/*/__init__.py)

.PHONY: all install run test validate stability bench clean distclean

all: install

$(STAMP): requirements.txt requirements-dev.txt setup.py setup.cfg package.xml $(PKG_INITS)
	test -x $(PY) || $(PYTHON) -m venv $(VENV)
	$(PY) -m pip install --upgrade pip
	$(PY) -m pip install -r requirements-dev.txt
	$(PY) -m pip install -e . --no-deps
	touch $@

install: $(STAMP)

run: install
	$(PY) -m sph_fsi.cli run $(SCENE) --out $(OUT) $(ARGS)
	@echo "Outputs in $(OUT)/ (timeseries.csv, summary.json, snapshots)"

# Tests get their own ROS domain (random 1..100) and stay on this host.
test: install
	export ROS_AUTOMATIC_DISCOVERY_RANGE=LOCALHOST; \
	export ROS_DOMAIN_ID=$$(( RANDOM % 100 + 1 )); \
	echo "ROS_DOMAIN_ID=$$ROS_DOMAIN_ID"; \
	$(PY) -m pytest -q -p no:cacheprovider $(PYTEST_ARGS) test

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
