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
# make install: the dgpc command as a link in BINDIR (default ~/.local/bin, on PATH in most
# shells' defaults), pointing into this checkout's .venv.
PREFIX ?= $(HOME)/.local
BINDIR ?= $(PREFIX)/bin
# pytest-xdist: one worker per core; tests sharing a module fixture stay on one (tests/conftest.py).
PARALLEL := -n auto --dist loadgroup

.DEFAULT_GOAL := help
.PHONY: help setup install uninstall test test-latest lock demo bench lint clean pipelines golden

help: ## Show the targets.
	@grep -hE '^[a-z-]+:.*## ' $(MAKEFILE_LIST) | awk -F':.*## ' '{printf "  make %-12s %s\n", $$1, $$2}'

$(STAMP): pyproject.toml $(LOCK)
	$(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet -c $(LOCK) --upgrade pip
	$(BIN)/python -m pip install --quiet -c $(LOCK) -e '.[test]'
	touch $(STAMP)

setup: $(STAMP) ## Create .venv and install dgpc with its test extras, pinned by constraints.txt.

# How a shell reaches `dgpc`: this checkout's link on PATH, else the two ways to get there.
REACH = if [ "$$(command -v dgpc)" = "$(BINDIR)/dgpc" ] && \
	    [ "$$(readlink $(BINDIR)/dgpc)" = "$(abspath $(BIN))/dgpc" ]; then \
	    echo "dgpc: on your PATH ($(BINDIR)/dgpc, make install): type 'dgpc --help'"; \
	  else \
	    echo "dgpc: the command is $(BIN)/dgpc; to type 'dgpc ...' as the README does, run \
	'source $(BIN)/activate' in your shell, or 'make install' once (puts dgpc on PATH)"; \
	  fi

install: setup ## Put the dgpc command on PATH: a link BINDIR/dgpc (~/.local/bin) to .venv/bin/dgpc.
	@mkdir -p "$(BINDIR)"
	@if [ -e "$(BINDIR)/dgpc" ] && [ ! -L "$(BINDIR)/dgpc" ]; then \
	    echo "install: $(BINDIR)/dgpc exists and is not a link: left alone (give BINDIR=DIR)" >&2; \
	    exit 1; fi
	@ln -sfn "$(abspath $(BIN))/dgpc" "$(BINDIR)/dgpc"
	@echo "install: $(BINDIR)/dgpc -> $(abspath $(BIN))/dgpc"
	@case ":$$PATH:" in *":$(BINDIR):"*) \
	    echo "install: $(BINDIR) is on your PATH: type 'dgpc --help' (a new shell may need 'hash -r')";; \
	  *) echo "install: $(BINDIR) is not on your PATH: add  export PATH=\"$(BINDIR):\$$PATH\"  to your shell's profile (~/.bashrc, ~/.zshrc), then open a new shell";; \
	esac

uninstall: ## Remove the link make install made (only if it points into this checkout).
	@if [ -L "$(BINDIR)/dgpc" ] && [ "$$(readlink "$(BINDIR)/dgpc")" = "$(abspath $(BIN))/dgpc" ]; then \
	    rm "$(BINDIR)/dgpc" && echo "uninstall: removed $(BINDIR)/dgpc"; \
	  else echo "uninstall: $(BINDIR)/dgpc is not this checkout's link: left alone"; fi

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
	@$(REACH)

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

clean: ## Remove the virtualenv and generated output (make uninstall first if you ran make install).
	rm -rf $(VENV) $(LATEST) $(DEMO) out .pytest_cache .ruff_cache *.egg-info
