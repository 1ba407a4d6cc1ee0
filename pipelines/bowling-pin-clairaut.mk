# Verification (paper Fig. 11): a twisted net on the bowling pin, fitted to the pin's surface;
# its u-lines become geodesics that are not meridians and satisfy Clairaut's r cos α = const.
PIN_M := $(call rows_or,41)
PIN_N := $(call cols_or,21)
PIN   := $(OUT)/bowling-pin-clairaut

$(PIN)/init.json:
	@mkdir -p $(@D)
	$(DGPC) init --surface revolution --profile bowling-pin --rows $(PIN_M) --cols $(PIN_N) \
	    --twist 3.0 --reference-out $(PIN)/pin-ref.obj -o $(basename $@) --force

# Fitted to the triangulated pin, R settles near 1e-9 at 81 rows (closest points hop between
# facets); the tolerance leaves it a margin.
$(PIN)/pin.json: $(PIN)/init.json
	$(DGPC) optimize $(basename $<) --mode fit --reference $(PIN)/pin-ref.obj --tol 1e-8 \
	    -o $(basename $@) --force

.PHONY: pipeline-bowling-pin-clairaut
pipeline-bowling-pin-clairaut: setup $(PIN)/pin-report-index.html ## Bowling pin: Clairaut verification and plot (Fig. 11).
	@echo "bowling-pin-clairaut: figures $(PIN)/pin-report-index.html"
