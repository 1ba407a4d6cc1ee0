# dgpc — make targets. A fresh machine needs only Python ≥ 3.11 and make.
PYTHON ?= python3
VENV   := .venv
BIN    := $(VENV)/bin
STAMP  := $(VENV)/.installed
DEMO   := demo-out

.DEFAULT_GOAL := help
.PHONY: help setup test demo bench lint clean

help: ## Show the targets.
	@grep -E '^[a-z-]+:.*## ' $(MAKEFILE_LIST) | awk -F':.*## ' '{printf "  make %-8s %s\n", $$1, $$2}'

$(STAMP): pyproject.toml
	$(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --upgrade pip
	$(BIN)/python -m pip install --quiet -e '.[test]'
	touch $(STAMP)

setup: $(STAMP) ## Create .venv and install dgpc with its test extras.

test: setup ## Run the test suite.
	$(BIN)/python -m pytest -q

lint: setup ## Run ruff.
	$(BIN)/ruff check dgpc_cli tests benchmarks

demo: setup ## Run the main job on the built-in sample; prints where the result is.
	@mkdir -p $(DEMO)
	$(BIN)/dgpc init --surface revolution --profile bowling-pin --rows 41 --cols 21 \
	    --twist 0.5 --reference-out $(DEMO)/pin-reference.obj -o $(DEMO)/pin-initial --force
	$(BIN)/dgpc optimize $(DEMO)/pin-initial --mode fit --reference $(DEMO)/pin-reference.obj \
	    -o $(DEMO)/pin --force
	@echo "result: $(DEMO)/pin.json and $(DEMO)/pin.obj (metrics: $(BIN)/dgpc inspect $(DEMO)/pin)"

bench: setup ## Solver speed at the paper's sizes beside a plain spsolve reference.
	$(BIN)/python benchmarks/solver_bench.py
	$(BIN)/python benchmarks/closest_points_bench.py
	$(BIN)/python benchmarks/nesting_bench.py

clean: ## Remove the virtualenv and generated output.
	rm -rf $(VENV) $(DEMO) .pytest_cache .ruff_cache *.egg-info
