# Geodesic gridshell (paper Fig. 14): two transversal geodesic nets on one reference, running
# beyond it (--extend: a tenth of its diagonal) so that the laths cover all of it, each
# fitted, then the laths of both families with their cut list.
GRID_M := $(call rows_or,35)
GRID_N := $(call cols_or,25)
GRID_EXTEND := 0.1
GRID   := $(OUT)/gridshell

$(GRID)/a0.json: samples/meshes/gridshell.obj
	@mkdir -p $(@D)
	$(DGPC) init $< --method geodesic --direction 1,0,0 --extend $(GRID_EXTEND) \
	    --rows $(GRID_M) --cols $(GRID_N) -o $(basename $@) --force

$(GRID)/b0.json: samples/meshes/gridshell.obj
	@mkdir -p $(@D)
	$(DGPC) init $< --method geodesic --direction 0,1,0 --extend $(GRID_EXTEND) \
	    --rows $(GRID_M) --cols $(GRID_N) -o $(basename $@) --force

# Fitted to the triangle mesh, R settles near 1e-9 (closest points hop between facets); the
# tolerance leaves it a margin.
$(GRID)/%.json: $(GRID)/%0.json
	$(DGPC) optimize $(basename $<) --mode fit --tol 1e-8 -o $(basename $@) --force

$(GRID)/laths.json: $(GRID)/a.json $(GRID)/b.json
	$(DGPC) laths $(basename $^) -o $(basename $@) --force

.PHONY: pipeline-gridshell
pipeline-gridshell: setup $(GRID)/laths-report-index.html $(GRID)/a-report-index.html ## Gridshell: two lath families and the cut list (Fig. 14).
	@echo "gridshell: $(GRID)/laths.json, $(GRID)/laths.csv, figures" \
	    "$(GRID)/laths-report-index.html $(GRID)/a-report-index.html"
