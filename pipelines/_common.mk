# Shared settings of pipelines/*.mk (included from the main Makefile).
# OUT: output root (each pipeline writes into $(OUT)/NAME/); ROWS, COLS: net size override
# (each pipeline has its own defaults); DGPC: the command.
OUT  ?= out
DGPC ?= $(BIN)/dgpc -q
# Fabrication tolerances of the drags and molds (optimize --max-strain/--gpc-tol, extract-mold
# --max-strain): 0.3 mm per metre by default; coarse nets (the golden tests' small versions)
# are stiffer and reach less.
MAX_STRAIN ?= 3e-4
GPC_TOL    ?= 1e-4
DRAG_TOL   := --max-strain $(MAX_STRAIN) --gpc-tol $(GPC_TOL)
PIPELINES := gehry-facade timber-cladding felt-developable bowling-pin-clairaut gridshell gallery
# $(call size,DEFAULT_ROWS,DEFAULT_COLS) -> ROWSxCOLS, ROWS/COLS overriding the defaults
rows_or = $(if $(ROWS),$(ROWS),$(1))
# Figures of an artifact: DIR/STEM-report-index.html (+ PNGs) from DIR/STEM.json.
%-report-index.html: %.json
	$(DGPC) report $(basename $<) -o $*-report --force >/dev/null

cols_or = $(if $(COLS),$(COLS),$(1))

# Handle files of a net size that is not committed: made by the sample generator.
samples/handles/%.json:
	$(BIN)/python samples/generate.py --size $(lastword $(subst -, ,$*))
