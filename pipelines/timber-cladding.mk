# Timber cladding (paper Fig. 2, 18): a wall isometric to a surface of revolution (the meridian
# net of samples/profiles/wall.csv bent by Minding's λ = 0.85, reached by isometric optimization
# towards handle targets), congruent planar strips, one cutting template, DXF cut sheets.
WALL_M := $(call rows_or,21)
WALL_N := $(call cols_or,13)
WALL   := $(OUT)/timber-cladding
# The wall is 6 m tall (net units: m); its boards are cut from 6.1 m × 2.5 m LVL panels by a
# CNC router (6 mm bit: 8 mm between parts), the ids engraved as single strokes.
WALL_SHEET := 6100x2500
WALL_LABEL := --label-style stroke
WALL_CAM   := --tool router --tool-diameter 6mm $(WALL_LABEL)

$(WALL)/base.json: samples/profiles/wall.csv
	@mkdir -p $(@D)
	$(DGPC) init --surface revolution --profile $< --rows $(WALL_M) --cols $(WALL_N) \
	    --span 60 --units m -o $(basename $@) --force

$(WALL)/wall.json: $(WALL)/base.json samples/handles/wall-$(WALL_M)x$(WALL_N).json
	$(DGPC) optimize $(basename $<) --mode isometric --handles $(word 2,$^) --steps 5 \
	    $(DRAG_TOL) -o $(basename $@) --force

$(WALL)/strips.json: $(WALL)/wall.json
	$(DGPC) planarize-strips $(basename $<) -o $(basename $@) --force

$(WALL)/flat.json: $(WALL)/strips.json
	$(DGPC) unfold $(basename $<) $(WALL_LABEL) -o $(basename $@) --force

$(WALL)/sheets.json: $(WALL)/flat.json
	$(DGPC) nest $(basename $<) --sheet $(WALL_SHEET) $(WALL_CAM) -o $(basename $@) --force

# One page of figures: the net (with its strain against the start), the strips, the developed
# parts and the cut sheets, each linking its own page of metrics.
$(WALL)/report-index.html: $(WALL)/wall.json $(WALL)/strips.json $(WALL)/flat.json \
    $(WALL)/sheets.json
	$(DGPC) report $(basename $^) -o $(WALL)/report --force >/dev/null

.PHONY: pipeline-timber-cladding
pipeline-timber-cladding: setup $(WALL)/sheets.json $(WALL)/report-index.html ## Timber cladding: congruent strips, DXF cut sheets (Fig. 2, 18).
	@echo "timber-cladding: figures $(WALL)/report-index.html"
	@echo "timber-cladding: $$(ls $(WALL)/sheets.sheet*.dxf | tr '\n' ' ')"
	@echo "timber-cladding: cut list $(WALL)/flat.parts.csv: $$(awk -F, 'NR > 1 {printf "%s%s x%s (score lines %s: %s)", (NR > 2 ? ", " : ""), $$1, $$2, $$(NF - 1), $$NF}' $(WALL)/flat.parts.csv)"
