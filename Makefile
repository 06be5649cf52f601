# voidcross: two commands do all the set-up on a fresh machine.
#   make demo   create .venv, install, run the end-to-end pipeline
#   make test   create .venv, install, run the unit tests (benchmarks excluded)
SHELL := /bin/bash
PYTHON ?= $(shell command -v python3.11 || command -v python3)
VENV := .venv
BIN := $(VENV)/bin
STAMP := $(VENV)/.installed-stamp
PIP_LOG := $(VENV)/pip-install.log

.PHONY: demo test bench boundary soak lint clean-venv help

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

demo: $(STAMP)
	$(BIN)/voidcross pipeline

test: $(STAMP)
	$(BIN)/python -m pytest -q

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
