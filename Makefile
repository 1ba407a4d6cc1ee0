# dgpc — make targets. A fresh machine needs only Python ≥ 3.11 and make.
PYTHON ?= python3
VENV   := .venv
BIN    := $(VENV)/bin
STAMP  := $(VENV)/.installed
DEMO   := demo-out

.DEFAULT_GOAL := help
.PHONY: help setup test demo bench lint clean pipelines golden

help: ## Show the targets.
	@grep -hE '^[a-z-]+:.*## ' $(MAKEFILE_LIST) | awk -F':.*## ' '{printf "  make %-8s %s\n", $$1, $$2}'

$(STAMP): pyproject.toml
	$(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --upgrade pip
	$(BIN)/python -m pip install --quiet -e '.[test]'
	touch $(STAMP)

setup: $(STAMP) ## Create .venv and install dgpc with its test extras.

test: setup ## Run the test suite.
	$(BIN)/python -m pytest -q

lint: setup ## Run ruff.
	$(BIN)/ruff check dgpc_cli tests benchmarks samples

demo: setup ## Run the main job (timber cladding) on the embedded sample; prints where the cut sheets are.
	@$(MAKE) --no-print-directory pipeline-timber-cladding OUT=$(DEMO)

bench: setup ## Solver speed at the paper's sizes beside a plain spsolve reference.
	$(BIN)/python benchmarks/solver_bench.py
	$(BIN)/python benchmarks/closest_points_bench.py
	$(BIN)/python benchmarks/nesting_bench.py

# Pipelines of the paper's applications (pipelines/*.mk): make pipeline-NAME, into $(OUT)/NAME/.
include pipelines/_common.mk
include $(filter-out pipelines/_common.mk,$(sort $(wildcard pipelines/*.mk)))

pipelines: $(addprefix pipeline-,$(PIPELINES)) ## Run every pipeline (out/NAME/; ROWS=, COLS= for size).

golden: setup ## Refresh tests/golden/ from small pipeline runs (only after a reviewed change).
	$(BIN)/python tests/golden/refresh.py

clean: ## Remove the virtualenv and generated output.
	rm -rf $(VENV) $(DEMO) out .pytest_cache .ruff_cache *.egg-info
