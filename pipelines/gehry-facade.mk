# Gehry-type facade (paper Fig. 1, 16, 17): one surface of revolution, four isometric
# deformations of its meridian net (handles from samples/generate.py), one mold for all four,
# and the panel-to-mold map sheet beside the cut sheets of the first facade's strips.
GEHRY_M   := $(call rows_or,21)
GEHRY_N   := $(call cols_or,13)
GEHRY     := $(OUT)/gehry-facade
# The facade is 5 m tall (net units: m); its panels are cut from 6 m × 1.25 m metal sheets.
GEHRY_SHEET := 6000x1250
GEHRY_DEF := $(foreach k,1 2 3 4,$(GEHRY)/facade-$(k).json)

$(GEHRY)/base.json: samples/profiles/gehry.csv
	@mkdir -p $(@D)
	$(DGPC) init --surface revolution --profile $< --rows $(GEHRY_M) --cols $(GEHRY_N) \
	    --span 90 --units m -o $(basename $@) --force

$(GEHRY)/facade-%.json: $(GEHRY)/base.json samples/handles/gehry-%-$(GEHRY_M)x$(GEHRY_N).json
	$(DGPC) optimize $(basename $<) --mode isometric --handles $(word 2,$^) --steps 5 \
	    $(DRAG_TOL) -o $(basename $@) --force

# The compact mold (--lambda compact): the full-turn surface of revolution isometric to the
# facades, about a quarter of their radius, turned on a lathe (the paper's "comparably small"
# mold); the default, --lambda design, would be the 90° design surface itself.
$(GEHRY)/mold.json: $(GEHRY_DEF)
	$(DGPC) extract-mold $(basename $^) --lambda compact --panel-size 2 --max-strain $(MAX_STRAIN) \
	    -o $(basename $@) --force

$(GEHRY)/strips.json: $(GEHRY)/facade-1.json
	$(DGPC) planarize-strips $(basename $<) -o $(basename $@) --force

$(GEHRY)/flat.json: $(GEHRY)/strips.json
	$(DGPC) unfold $(basename $<) -o $(basename $@) --force

$(GEHRY)/sheets.json: $(GEHRY)/flat.json $(GEHRY)/mold.json
	$(DGPC) nest $(basename $<) --mold $(basename $(word 2,$^)) \
	    --sheet $(GEHRY_SHEET) -o $(basename $@) --force

# One page of figures: the first facade (with its strain against the start), its strips, flat
# parts and cut sheets with the panel-to-mold map, and the mold, each linking its own page.
$(GEHRY)/report-index.html: $(GEHRY)/facade-1.json $(GEHRY)/strips.json $(GEHRY)/flat.json \
    $(GEHRY)/sheets.json $(GEHRY)/mold.json
	$(DGPC) report $(basename $^) -o $(GEHRY)/report --force >/dev/null

.PHONY: pipeline-gehry-facade
pipeline-gehry-facade: setup $(GEHRY)/sheets.json $(GEHRY)/report-index.html ## Gehry facade: 4 deformations, 1 mold (Fig. 1, 16, 17).
	@echo "gehry-facade: $(GEHRY)/mold.json, $(GEHRY)/sheets.moldmap.dxf, figures" \
	    "$(GEHRY)/report-index.html"
