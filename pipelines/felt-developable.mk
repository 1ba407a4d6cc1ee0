# Nearly developable felt shape (paper Fig. 8, 12, 15): geodesic net on the bent sheet,
# developable optimization (constant strip width, rulings), planar strips, developed strips.
FELT_M := $(call rows_or,41)
FELT_N := $(call cols_or,25)
FELT   := $(OUT)/felt-developable

$(FELT)/init.json: samples/meshes/felt.obj
	@mkdir -p $(@D)
	$(DGPC) init $< --method geodesic --rows $(FELT_M) --cols $(FELT_N) -o $(basename $@) --force

$(FELT)/felt.json: $(FELT)/init.json samples/meshes/felt.obj
	$(DGPC) optimize $(basename $<) --mode developable --reference samples/meshes/felt.obj \
	    -o $(basename $@) --force

$(FELT)/strips.json: $(FELT)/felt.json
	$(DGPC) planarize-strips $(basename $<) -o $(basename $@) --force

$(FELT)/flat.json: $(FELT)/strips.json
	$(DGPC) unfold $(basename $<) -o $(basename $@) --force

.PHONY: pipeline-felt-developable
pipeline-felt-developable: setup $(FELT)/felt-report-index.html \
    $(FELT)/flat-report-index.html ## Felt: nearly developable fit, developed strips (Fig. 8, 12, 15).
	@echo "felt-developable: $(FELT)/flat.json, figures $(FELT)/felt-report-index.html" \
	    "$(FELT)/flat-report-index.html"
