# Entry points: `make report` (main job) and `make test`. `make help` lists targets.
# Everything runs inside .venv, created on first use from the pinned requirements.lock.

SHELL := /bin/bash
PYTHON ?= python3
VENV := .venv
PY := $(VENV)/bin/python
STAMP := $(VENV)/.installed
BUILD := reports/build

.DEFAULT_GOAL := help

## help: list the targets
.PHONY: help
help:
	@grep -hE '^## ' $(MAKEFILE_LIST) | sed -e 's/^## /  /'

# The venv is a real file target: it is rebuilt only when the pins change.
$(STAMP): requirements.lock pyproject.toml
	@test -x $(PY) || $(PYTHON) -m venv $(VENV)
	$(PY) -m pip install --quiet --disable-pip-version-check -r requirements.lock
	@touch $(STAMP)

## venv: create .venv and install the pinned dependencies
.PHONY: venv
venv: $(STAMP)

## test: run the test suite on two workers (creates .venv when missing)
# pytest-xdist: two processes (`pytest FILE` alone runs serially); --dist loadfile keeps each
# file on one worker, so module fixtures (the report build, derivations) run once per file
# rather than once per worker. Bytecode is written even where PYTHONDONTWRITEBYTECODE is set
# (into the git-ignored __pycache__ folders): each worker then loads the project's modules and
# pytest's rewritten test modules from bytecode instead of compiling them, about 2 s of CPU per
# worker from the second run on. --max-worker-restart=0: a worker that dies (a test past pytest-timeout's
# limit ends its process) fails the run at once, naming the test it was running; with a replacement
# worker, xdist's file scheduling waited for ever (26 November 2026).
TEST_WORKERS ?= 2
.PHONY: test
test: $(STAMP)
	PYTHONDONTWRITEBYTECODE= $(PY) -m pytest -n $(TEST_WORKERS) --dist loadfile --max-worker-restart=0

## bench: time the solver, the survey analytics and the report build (results in reports/build/bench/)
.PHONY: bench
bench: $(STAMP)
	@mkdir -p $(BUILD)/bench
	@set -e; for f in tests/bench/bench_*.py; do echo "== $$f"; $(PY) $$f; done

# The report is a real file target. Its inputs: every data file, the solver, the survey
# analytics, the report code and templates, and other helpers' benchmark results (the
# report's own timing, bench/report.json, is not an input). One build writes all outputs;
# the stamp records that they are up to date, so a second `make report` does nothing and
# touching any input (e.g. a scene file) rebuilds.
REPORT_OUTPUTS := $(BUILD)/report.html $(BUILD)/verification.json $(BUILD)/paper.html $(BUILD)/paper.tex
REPORT_STAMP := $(BUILD)/.report.stamp
# (make's own wildcards, four levels deep, not `find`: a $(shell) costs a process on every
# make run, and a no-op `make report` should take well under 0.1 s)
DATA_ANY := $(wildcard data/* data/*/* data/*/*/* data/*/*/*/*)
DATA_DIRS := $(patsubst %/.,%,$(wildcard data/*/. data/*/*/. data/*/*/*/.))
PY_SOURCES := $(filter-out reports/build/%,$(wildcard $(foreach d,solver analysis reports,$(d)/*.py $(d)/*/*.py $(d)/*/*/*.py)))
REPORT_INPUTS := $(filter-out $(DATA_DIRS),$(DATA_ANY)) $(PY_SOURCES) \
	$(wildcard analysis/templates/* reports/templates/* solver/fonts/*) \
	$(filter-out $(BUILD)/bench/report.json,$(wildcard $(BUILD)/bench/*.json))

# As `make test`, bytecode is written even where PYTHONDONTWRITEBYTECODE is set: the project's
# modules and the templates' compiled code (reports/__pycache__/templates/), into git-ignored
# folders, so that a later build (after a data file changed) loads them instead of compiling.
$(REPORT_STAMP): $(STAMP) $(REPORT_INPUTS)
	@mkdir -p $(BUILD)
	PYTHONDONTWRITEBYTECODE= $(PY) -m reports --out $(BUILD)
	@touch $@ && touch $(REPORT_OUTPUTS)

# An output deleted by hand is rebuilt (the outputs are never older than the stamp otherwise).
$(REPORT_OUTPUTS): $(REPORT_STAMP)
	@test -f $@ || { rm -f $(REPORT_STAMP) && $(MAKE) --no-print-directory $(REPORT_STAMP); }

## report: build the verification report and the reproducible paper into reports/build/
.PHONY: report
report: $(REPORT_OUTPUTS)

## clean: remove build outputs (keeps .venv)
.PHONY: clean
clean:
	rm -rf $(BUILD)

## distclean: remove build outputs and .venv
.PHONY: distclean
distclean: clean
	rm -rf $(VENV)
