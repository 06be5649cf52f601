# voidcross: two commands do all the set-up on a fresh machine.
#   make demo   create .venv, install, run the end-to-end pipeline
#   make test   create .venv, install, run the unit tests (benchmarks excluded)
SHELL := /bin/bash
PYTHON ?= $(shell command -v python3.11 || command -v python3)
VENV := .venv
BIN := $(VENV)/bin
STAMP := $(VENV)/.installed-stamp
PIP_LOG := $(VENV)/pip-install.log

.PHONY: demo test bench boundary soak lint clean-venv help clients setup

help:
	@echo "make demo | make test | make bench | make boundary | make soak | make lint"

$(BIN)/python:
	@$(PYTHON) -c 'import sys; sys.exit(0 if sys.version_info >= (3, 11) else 1)' || \
	  { echo "error: Python >= 3.11 is required (found $$($(PYTHON) --version 2>&1) at $(PYTHON))"; exit 2; }
	@echo "creating $(VENV) with $$($(PYTHON) --version)"
	@$(PYTHON) -m venv $(VENV)

# Reinstall only when the project metadata changed (editable install: code edits need none).
$(STAMP): pyproject.toml | $(BIN)/python
	@echo "installing voidcross[all,dev] into $(VENV) (log: $(PIP_LOG))"
	@$(BIN)/python -m pip install -q --upgrade pip > $(PIP_LOG) 2>&1 || true
	@$(BIN)/python -m pip install -q -e '.[all,dev]' >> $(PIP_LOG) 2>&1 || \
	  { echo "error: pip could not install voidcross[all,dev]; last lines of $(PIP_LOG):"; \
	    grep -iE 'error|could not|no matching' $(PIP_LOG) | tail -n 5; exit 1; }
	@touch $(STAMP)

# The real clients the tests drive (PrusaSlicer slices the exports, Chromium loads the report):
# installed from Debian's packages when missing and we are root with apt; otherwise a clear
# line says what will not be tested (under CI=true those tests fail instead of skipping).
CLIENTS := prusa-slicer chromium
# Debian libraries (not commands) the renders need: VTK draws offscreen through EGL with Mesa's
# software rasteriser (cubot_cad/render.py); checked with dpkg where there is one, installed with the clients.
GL_LIBS := libegl1 libegl-mesa0 libgl1-mesa-dri
clients:
	@missing=""; for c in $(CLIENTS); do command -v $$c >/dev/null 2>&1 || missing="$$missing $$c"; done; \
	if command -v dpkg >/dev/null 2>&1; then for p in $(GL_LIBS); do dpkg -s $$p >/dev/null 2>&1 || missing="$$missing $$p"; done; fi; \
	if [ -z "$$missing" ]; then exit 0; fi; \
	if [ "$$(id -u)" = 0 ] && command -v apt-get >/dev/null 2>&1; then \
	  echo "installing$$missing from Debian's packages (log: .clients-install.log)"; \
	  { apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq $$missing; } \
	    > .clients-install.log 2>&1 || { echo "error: apt-get could not install$$missing; see .clients-install.log"; \
	    tail -n 5 .clients-install.log; exit 1; }; \
	else \
	  echo "warning:$$missing not installed and no root apt-get here: install them (Debian: apt-get install$$missing)"; \
	  echo "         or the slicing and browser tests skip (they fail under CI=true)"; \
	fi

# The two set-up steps side by side (pip's downloads and apt's are independent): on a fresh
# machine the shorter one costs nothing. Their logs go to files, so the lines do not mix.
setup:
	@$(MAKE) --no-print-directory -j2 $(STAMP) clients

demo: setup
	$(BIN)/voidcross pipeline

test: setup
	$(BIN)/python -m pytest -q -n auto --dist loadgroup --durations=25

bench: $(STAMP)
	$(BIN)/python -m pytest -q -m bench --benchmark-enable tests

# the thesis's crossing boundaries, 50 seeds per case over several widths (issue 13; ~15 min on 2 cores)
boundary: $(STAMP)
	$(BIN)/python -m pytest -q -s -m bench tests/swarm_sim/test_boundaries_at_scale.py

# whole randomised runs, every invariant checked each step (docs/experiments.md has the 10,000-run figure)
soak: $(STAMP)
	$(BIN)/voidcross sim soak --runs 1000 --workers 2

lint: $(STAMP)
	$(BIN)/ruff check .

clean-venv:
	rm -rf $(VENV)

# API reference of voidcross.api (and the records it returns) from the docstrings, as HTML in docs/api/
# (pdoc, from the dev extra; docs/api.md is the hand-written guide)
.PHONY: api-docs
api-docs: $(STAMP)
	rm -rf docs/api
	$(BIN)/pdoc --docformat google --no-show-source -o docs/api voidcross.api swarm_sim.runner structure_fem.limits
	@echo "wrote docs/api/index.html"

# regenerate the docs' generated blocks (decision tables, structure_fem numbers) from the code;
# the tests fail when they are stale
.PHONY: docs
docs: $(STAMP)
	$(BIN)/python -m swarm_sim.decision_docs docs/swarm_sim.md
	$(BIN)/python -m structure_fem.outputs.docs_blocks docs/structure_fem.md README.md
