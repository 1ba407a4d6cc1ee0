# Gallery (paper Fig. 19): six surfaces of revolution, each twisted by a designer's drag into a
# freeform shape isometric to it (optimize --mode isometric, handles from samples/generate.py),
# each with its mold (extract-mold) and its developed strips (planarize-strips, unfold).
GALLERY_M     := $(call rows_or,21)
GALLERY_N     := $(call cols_or,13)
GALLERY       := $(OUT)/gallery
GALLERY_SHAPES := sphere-zone cylinder catenoid sphere bowling-pin wall
# profile and --span per shape (the same as HANDLE_SETS in samples/generate.py)
gallery_profile = $(if $(filter wall,$(1)),samples/profiles/wall.csv,$(1))
gallery_span    = $(if $(filter wall,$(1)),60,90)

$(GALLERY)/%-base.json: samples/profiles/wall.csv
	@mkdir -p $(@D)
	$(DGPC) init --surface revolution --profile $(call gallery_profile,$*) --units m \
	    --rows $(GALLERY_M) --cols $(GALLERY_N) --span $(call gallery_span,$*) \
	    -o $(basename $@) --force

$(GALLERY)/%-net.json: $(GALLERY)/%-base.json \
    samples/handles/gallery-%-$(GALLERY_M)x$(GALLERY_N).json
	$(DGPC) optimize $(basename $<) --mode isometric --handles $(word 2,$^) --steps 5 \
	    $(DRAG_TOL) -o $(basename $@) --force

$(GALLERY)/%-mold.json: $(GALLERY)/%-net.json
	$(DGPC) extract-mold $(basename $<) --max-strain $(MAX_STRAIN) -o $(basename $@) --force

$(GALLERY)/%-strips.json: $(GALLERY)/%-net.json
	$(DGPC) planarize-strips $(basename $<) -o $(basename $@) --force

$(GALLERY)/%-flat.json: $(GALLERY)/%-strips.json
	$(DGPC) unfold $(basename $<) -o $(basename $@) --force

GALLERY_OUT := $(foreach s,$(GALLERY_SHAPES),$(GALLERY)/$(s)-mold.json \
    $(GALLERY)/$(s)-flat.json $(GALLERY)/$(s)-net-report-index.html)

.PRECIOUS: $(GALLERY)/%-base.json $(GALLERY)/%-net.json $(GALLERY)/%-strips.json
.PHONY: pipeline-gallery
pipeline-gallery: setup $(GALLERY_OUT) ## Gallery: six freeform shapes isometric to surfaces of revolution (Fig. 19).
	@echo "gallery: $(GALLERY)/*-net-report-index.html, molds $(GALLERY)/*-mold.json"
