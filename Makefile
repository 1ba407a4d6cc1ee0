# dgpc — make targets. A fresh machine needs only Python ≥ 3.11 and make.
PYTHON ?= python3
VENV   := .venv
BIN    := $(VENV)/bin
STAMP  := $(VENV)/.installed
DEMO   := demo-out
# The pinned set `make setup` installs: what CI last passed with (pip constraints format).
# pyproject.toml keeps the ranges, for users who install dgpc into an environment of theirs.
LOCK   := constraints.txt
LATEST := .venv-latest
# pytest-xdist: one worker per core; tests sharing a module fixture stay on one (tests/conftest.py).
PARALLEL := -n auto --dist loadgroup

.DEFAULT_GOAL := help
.PHONY: help setup test test-latest lock demo bench lint clean pipelines golden

help: ## Show the targets.
	@grep -hE '^[a-z-]+:.*## ' $(MAKEFILE_LIST) | awk -F':.*## ' '{printf "  make %-12s %s\n", $$1, $$2}'

$(STAMP): pyproject.toml $(LOCK)
	$(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet -c $(LOCK) --upgrade pip
	$(BIN)/python -m pip install --quiet -c $(LOCK) -e '.[test]'
	touch $(STAMP)

setup: $(STAMP) ## Create .venv and install dgpc with its test extras, pinned by constraints.txt.

test: setup ## Run the test suite (in parallel: one worker per core).
	$(BIN)/python -m pytest -q $(PARALLEL)

test-latest: ## Run the tests with the newest releases pyproject.toml allows; reports, never fails.
	rm -rf $(LATEST) && $(PYTHON) -m venv $(LATEST)
	$(LATEST)/bin/python -m pip install --quiet --upgrade pip
	$(LATEST)/bin/python -m pip install --quiet -e '.[test]'
	@$(LATEST)/bin/python -m pip freeze --exclude-editable | grep -vi '^dgpc' \
	    | diff -U0 $(LOCK) - | grep '^[-+][A-Za-z]' \
	    | sed 's/^-/test-latest: pinned /; s/^+/test-latest: newest /' || \
	    echo "test-latest: the newest releases are the pinned ones"
	@$(LATEST)/bin/python -m pytest -q $(PARALLEL) -o cache_dir=$(LATEST)/.pytest_cache \
	    && echo "test-latest: green with the newest releases" \
	    || echo "test-latest: FAILURES with the newest releases (above); constraints.txt keeps CI on the pinned set"

lock: ## Refresh constraints.txt with the newest releases pyproject.toml allows (then run make test).
	rm -rf $(LATEST) && $(PYTHON) -m venv $(LATEST)
	$(LATEST)/bin/python -m pip install --quiet --upgrade pip
	$(LATEST)/bin/python -m pip install --quiet -e '.[test]'
	( echo "# Pinned set of make setup (pip constraints). Refresh: make lock; review; make test."; \
	  echo "# Made on $$(uname -m) with $$($(LATEST)/bin/python -V)."; \
	  $(LATEST)/bin/python -m pip freeze --all --exclude-editable \
	    | grep -viE '^(dgpc|setuptools|wheel)[=@ ]' ) > $(LOCK).new && mv $(LOCK).new $(LOCK)

lint: setup ## Run ruff.
	$(BIN)/ruff check dgpc_cli tests benchmarks samples

demo: setup ## Run the main job (timber cladding) on the embedded sample; prints where the cut sheets are.
	@$(MAKE) --no-print-directory pipeline-timber-cladding OUT=$(DEMO)

bench: setup ## Solver speed beside plain spsolve, whole commands, iterations, start-up; batch scaling.
	$(BIN)/python benchmarks/solver_bench.py
	$(BIN)/python benchmarks/closest_points_bench.py
	$(BIN)/python benchmarks/nesting_bench.py
	$(BIN)/python benchmarks/command_bench.py
	$(BIN)/python benchmarks/batch_bench.py
	$(BIN)/python benchmarks/edit_bench.py
	$(BIN)/python benchmarks/roof_bench.py

# Pipelines of the paper's applications (pipelines/*.mk): make pipeline-NAME, into $(OUT)/NAME/.
include pipelines/_common.mk
include $(filter-out pipelines/_common.mk,$(sort $(wildcard pipelines/*.mk)))

# Projects of many patches (samples/projects/*.toml) through `dgpc batch` on a local Dask
# cluster (WORKERS=N worker processes, default one per core), into $(OUT)/NAME/.
BATCH_WORKERS = $(if $(WORKERS),--workers $(WORKERS))
.PHONY: pipeline-facade-batch pipeline-sweep-batch
pipeline-facade-batch: setup ## Gehry facade, 4 patches, 1 mold, 1 nesting: dgpc batch on Dask.
	$(BIN)/dgpc batch samples/projects/gehry-facade.toml -o $(OUT)/facade-batch $(BATCH_WORKERS)
	@echo "facade-batch: $(OUT)/facade-batch/index.html"

pipeline-sweep-batch: setup ## Design sweep: 12 twists of the first Gehry patch (dgpc batch).
	$(BIN)/dgpc batch samples/projects/gehry-sweep.toml -o $(OUT)/gehry-sweep $(BATCH_WORKERS)
	@echo "gehry-sweep: $(OUT)/gehry-sweep/index.html"

pipelines: $(addprefix pipeline-,$(PIPELINES)) ## Run every pipeline (out/NAME/; ROWS=, COLS= for size).

golden: setup ## Refresh tests/golden/ from small pipeline runs (only after a reviewed change).
	$(BIN)/python tests/golden/refresh.py

clean: ## Remove the virtualenv and generated output.
	rm -rf $(VENV) $(LATEST) $(DEMO) out .pytest_cache .ruff_cache *.egg-info
