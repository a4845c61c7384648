# The stages of a case as Make rules (CONTRACT.md "Cases"). Each case's Makefile sets
# CASE_DIR and includes this file. Every target depends on the files of the stage
# before, so `make` reruns only what is stale, and independent runs go in parallel
# under `make -j2`.
#
#   make fem              FE phase:           out/fem/fem_t*.h5, fem_history.csv
#   make transfer TT=2    FE -> particles:    out/tt2/particles.h5
#   make mpm TT=2         MPM from them:      out/tt2/mpm_final.h5, mpm_history.csv
#   make pure-mpm         MPM from geometry:  out/pure-mpm/
#   make pure-fem         FE to the MPM end:  out/pure-fem/ (+ particles for metrics)
#   make sweep            t_T = 0, 1, 2, ... while the FE mesh is not entangled,
#                         plus pure-mpm and pure-fem: out/sweep.csv
#   make report           out/report/report.md with its figures
#   make main             the README's main job: tt0, tt<main>, pure runs, report
#
# Variables: OUT=dir (default out/ next to case.toml), BUILD=dir (default build/ at
# the top of the repository), PYTHON (default /usr/bin/python3, Debian's, with h5py
# and matplotlib), THREADS (OpenMP threads per MPM run), VTK_EVERY (s between MPM VTK
# frames, default 1; 0 for every output step), MPM_FLAGS, FEM_FLAGS, TRANSFER_FLAGS.

ROOT    := $(abspath $(CASE_DIR)/../..)
BUILD   ?= $(ROOT)/build
BIN     ?= $(BUILD)/bin
PYTHON  ?= /usr/bin/python3
OUT     ?= $(CASE_DIR)/out
CASE    := $(CASE_DIR)/case.toml
TOOLS   := $(ROOT)/tools

FEM_SOLVE := $(BIN)/fem-solve
FEM2MPM   := $(BIN)/fem2mpm
MPM_SOLVE := $(BIN)/mpm-solve
METRICS   := $(BIN)/slide-metrics
PROGRAMS  := $(FEM_SOLVE) $(FEM2MPM) $(MPM_SOLVE) $(METRICS)

VTK_EVERY ?= 1
MPM_FLAGS += --vtk-every $(VTK_EVERY)
ifneq ($(THREADS),)
  MPM_FLAGS += --threads $(THREADS)
endif

# The case's own numbers (MAIN_TT, SWEEP_TTS, FEM_END, MPM_END, TAU_C), read once
# from case.toml by the same reader the programs use.
CASE_MK := $(OUT)/case.mk
ifeq ($(filter clean help,$(MAKECMDGOALS)),)
  -include $(CASE_MK)
endif
$(CASE_MK): $(CASE) | $(METRICS)
	@mkdir -p $(OUT)
	$(METRICS) case-info $(CASE) > $@.tmp && mv $@.tmp $@

$(PROGRAMS):
	@echo "missing $@: build the project first (cmake -S $(ROOT) -B $(BUILD) && cmake --build $(BUILD))" >&2
	@false

TT ?= $(MAIN_TT)
three_decimals = $(shell printf '%.3f' $(1))

FEM_DONE := $(OUT)/fem/fem_t$(call three_decimals,$(FEM_END)).h5
PURE_FEM := $(OUT)/pure-fem/particles_final.h5
PURE_MPM := $(OUT)/pure-mpm/mpm_final.h5
# The runs every sweep and main job compares against; a case without a failure stage
# (geostatic-4x4) has no pure-FE run.
ifeq ($(FEM_END),0)
  PURE_RUNS := $(PURE_MPM)
else
  PURE_RUNS := $(PURE_MPM) $(PURE_FEM)
endif

.PHONY: all main fem transfer mpm pure-mpm pure-fem sweep sweep-runs report clean help
.DELETE_ON_ERROR:
.SECONDARY:

all: main

help:
	@sed -n '/^#   make/,/^#$$/p' $(lastword $(MAKEFILE_LIST)) | sed 's/^# //'

# --------------------------------------------------------------------------- stages
fem: $(FEM_DONE)
$(FEM_DONE): $(CASE) $(FEM_SOLVE)
	$(FEM_SOLVE) $(CASE) -o $(OUT)/fem $(FEM_FLAGS)

transfer: $(OUT)/tt$(TT)/particles.h5
$(OUT)/tt%/particles.h5: $(FEM_DONE) $(FEM2MPM)
	$(FEM2MPM) $(OUT)/fem/fem_t$(call three_decimals,$*).h5 -o $@ --case $(CASE) $(TRANSFER_FLAGS)

# The main job transfers at t_T ≈ τc as the study prescribes, even where the toe
# elements have begun to fold (column-short: J_min = -0.004 at 2 s); their particles
# get the elements' reference volumes and the transfer report lists them. Sweeps only
# use checkpoints with (|J_t|/|J_0|)_min > 0 (METHOD.md §7).
$(OUT)/tt$(MAIN_TT)/particles.h5: TRANSFER_FLAGS += --allow-inverted

mpm: $(OUT)/tt$(TT)/mpm_final.h5
$(OUT)/tt%/mpm_final.h5: $(OUT)/tt%/particles.h5 $(MPM_SOLVE)
	$(MPM_SOLVE) $(CASE) -o $(OUT)/tt$* --particles $< $(MPM_FLAGS)

pure-mpm: $(PURE_MPM)
$(PURE_MPM): $(CASE) $(MPM_SOLVE)
	$(MPM_SOLVE) $(CASE) -o $(OUT)/pure-mpm $(MPM_FLAGS)

# Pure FE: the FE model run on to the MPM end time, measured through the same
# particles (element-wise transfer of its final state, folded elements included:
# small strain runs on through inversion) as the MPM runs.
pure-fem: $(PURE_FEM)
$(PURE_FEM): $(CASE) $(FEM_SOLVE) $(FEM2MPM)
	$(FEM_SOLVE) $(CASE) -o $(OUT)/pure-fem --until $(MPM_END) --no-vtk $(FEM_FLAGS)
	$(FEM2MPM) $(OUT)/pure-fem/fem_t$(call three_decimals,$(MPM_END)).h5 -o $@ \
	  --case $(CASE) --stress-interpolation element --allow-inverted --quiet

# --------------------------------------------------------------------------- sweep
# The valid transfer times are known only once the FE phase has run (the mesh must
# not have entangled), so `sweep` runs the FE phase, then asks for them.
sweep: fem
	+$(MAKE) -f $(firstword $(MAKEFILE_LIST)) sweep-runs \
	  TTS="$$($(METRICS) transfer-times $(CASE) $(OUT)/fem/fem_history.csv)"

sweep-runs: $(foreach t,$(TTS),$(OUT)/tt$(t)/mpm_final.h5) $(PURE_RUNS)
	$(METRICS) sweep $(CASE) $(OUT)

# --------------------------------------------------------------------------- report
report: $(OUT)/sweep.csv
	$(PYTHON) $(TOOLS)/plots.py $(CASE) $(OUT)
	$(PYTHON) $(TOOLS)/report.py $(CASE) $(OUT)
	@echo "report: $(OUT)/report/report.md"

$(OUT)/sweep.csv:
	@echo "no $@ yet: run 'make sweep' or 'make main' first" >&2
	@false

main: $(OUT)/tt0/mpm_final.h5 $(OUT)/tt$(MAIN_TT)/mpm_final.h5 $(PURE_RUNS)
	$(METRICS) sweep $(CASE) $(OUT)
	+$(MAKE) -f $(firstword $(MAKEFILE_LIST)) report

clean:
	rm -rf $(OUT)
