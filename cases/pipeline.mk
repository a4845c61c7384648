# The stages of a case as Make rules (docs/contract.md, "Cases and the Make pipeline"). Each case's Makefile sets
# CASE_DIR and includes this file. Every target depends on the files of the stage
# before, so `make` reruns only what is stale (a second `make main` runs nothing), and
# independent runs go in parallel under `make -j2`.
#
#   make                  the same as make main
#   make main             the README's main job: tt0, tt<main>, pure runs, report
#   make fem              FE phase:           out/fem/fem_t*.h5, fem_history.csv
#                         (also fem_t<T>.h5 at T, the last output inside the
#                         recommended transfer zone, e.g. fem_t1.300.h5)
#   make transfer TT=2    FE -> particles:    out/tt2/particles.h5
#   make mpm TT=2         MPM from them:      out/tt2/mpm_final.h5, mpm_history.csv
#   make pure-mpm         MPM from geometry:  out/pure-mpm/
#   make pure-fem         FE to the MPM end:  out/pure-fem/ (+ particles for metrics)
#   make sweep            t_T = 0, 1, 2, ... while the FE mesh is not entangled,
#                         plus pure-mpm and pure-fem: out/sweep.csv
#   make report           out/report/report.md with its figures, from every finished
#                         run in out/ (re-measured when a run is newer than sweep.csv;
#                         with the main transfer's run, also out/tt<main>/after-0.5s/,
#                         its state 0.5 s after t_T, for the σyy figure)
#   make fos              the factor of safety by strength reduction: out/fos/
#                         (strength_reduction.txt; then `make report` shows it)
#   make sweep-plan       the runs `make sweep` makes (after the FE phase)
#   make clean            removes what the pipeline made in OUT (only there: a folder
#                         it marked, never /, the home folder or the repository)
#   make help             this list
#
# Variables (make VAR=value ...):
#   TT=t        transfer time in s for transfer and mpm (default: the case's main
#               one): an FE checkpoint time, rounded to the checkpoint names' three
#               decimals; TT=1.3, 1.30 and 1.3004 all mean fem_t1.300.h5 and run tt1.3
#   OUT=dir     where the runs go (default out/ next to case.toml); a relative dir is
#               taken from the directory make was called from (`make -C`, too)
#   BUILD=dir   the build, with the source tree's pipeline (default build/ at its top;
#               the installed pipeline uses the installed programs)
#   BIN=dir     the programs (default BUILD/bin)
#   PYTHON=py   for the plots and the report (default /usr/bin/python3, Debian's,
#               with h5py and matplotlib)
#   THREADS=n   OpenMP threads per MPM run or rank (unset: all cores for a run made alone,
#               1 per run under make -j, so that two runs do not oversubscribe)
#   MPIRUN=cmd  runs mpm-solve under MPI, e.g. MPIRUN="mpirun -q -np 2" with
#               BUILD=build-mpi (docs/parallel.md); unset: one process
#   VTK_EVERY=s seconds between MPM VTK frames (default 1; 0: every output step)
#   FEM_FLAGS, TRANSFER_FLAGS, MPM_FLAGS   more options for fem-solve, fem2mpm and
#               mpm-solve (their --help lists them)
#
# Every run is remade when it is missing or older than what it is made from, whatever
# else exists: a later `make main` makes the pure runs a `make mpm TT=0 report` skipped.

.DEFAULT_GOAL := main
PIPELINE_MK := $(lastword $(MAKEFILE_LIST))
include $(dir $(PIPELINE_MK))paths.mk
CASE    := $(CASE_DIR)/case.toml

FEM_SOLVE := $(BIN)/fem-solve
FEM2MPM   := $(BIN)/fem2mpm
MPM_SOLVE := $(BIN)/mpm-solve
METRICS   := $(BIN)/slide-metrics
PROGRAMS  := $(FEM_SOLVE) $(FEM2MPM) $(MPM_SOLVE) $(METRICS)

VTK_EVERY ?= 1
# Expanded in the recipes, where MAKEFLAGS carries -j (it does not while parsing).
mpm_threads = $(or $(THREADS),$(if $(filter-out -j1,$(filter -j%,$(MAKEFLAGS))),1))
MPM_OPTIONS = --vtk-every $(VTK_EVERY) $(if $(mpm_threads),--threads $(mpm_threads))

# The case's own numbers (MAIN_TT, SWEEP_TTS, FEM_END, MPM_END, TAU_C), its mesh file
# (MESH_FILE, a Gmsh case's .msh) and the other files it names (CASE_FILES: the base
# motion's records), read once from case.toml by the same reader the programs use. The runs
# made from the case depend on all of them: editing a motion record reruns the FE phase.
# A case file the reader refuses stops make there, with the reader's one-line error.
CASE_MK := $(OUT)/case.mk
ifeq ($(filter clean help,$(MAKECMDGOALS)),)
  include $(CASE_MK)
endif
$(CASE_MK): $(CASE) | $(METRICS) $(OUT_STAMP)
	$(METRICS) case-info $(CASE) > $@.tmp && mv $@.tmp $@

CASE_INPUTS = $(CASE) $(MESH_FILE) $(CASE_FILES)

$(PROGRAMS):
	@echo "missing $@: $(if $(SLIDE_INSTALLED_BIN),install the programs again (cmake --install BUILD --prefix PREFIX) or give BIN=dir,build the project first (cmake -S $(ROOT) -B $(BUILD) && cmake --build $(BUILD)))" >&2
	@false

# A transfer time in its one spelling: rounded to the three decimals of the checkpoint
# names, trailing zeros dropped (1.30 -> 1.3, 0.0 -> 0); "invalid" if not a time.
canonical_time = $(shell awk -v t='$(1)' 'BEGIN { \
  if (t !~ /^([0-9]+\.?[0-9]*|\.[0-9]+)([eE][-+]?[0-9]+)?$$/) { print "invalid"; exit } \
  x = sprintf("%.3f", t + 0); sub(/0+$$/, "", x); sub(/\.$$/, "", x); print x }')
three_decimals = $(shell printf '%.3f' $(1))

ifdef TT
  RUN_TT := $(call canonical_time,$(TT))
  ifeq ($(RUN_TT),invalid)
    $(error TT=$(TT) is not a transfer time: give an FE checkpoint time in s, e.g. TT=1.3)
  endif
else
  RUN_TT = $(MAIN_TT)
endif

FEM_DONE := $(OUT)/fem/fem_t$(call three_decimals,$(FEM_END)).h5
# A TT without an FE checkpoint, once the FE phase has run: one line before anything
# runs, naming the times there are. (Before the FE phase the transfer rule checks it.)
fem_times = $(shell ls $(OUT)/fem 2> /dev/null | sed -n 's/^fem_t\(.*\)\.h5$$/\1/p' | sort -g | \
              awk '{ printf "%s%g", (NR > 1 ? " " : ""), $$1 }')
ifdef TT
  ifneq ($(wildcard $(FEM_DONE)),)
    ifeq ($(wildcard $(OUT)/fem/fem_t$(call three_decimals,$(RUN_TT)).h5),)
      $(error no FE checkpoint at t_T = $(RUN_TT) s ($(OUT)/fem/fem_t$(call three_decimals,$(RUN_TT)).h5); the FE phase wrote t_T = $(fem_times))
    endif
  endif
endif
PURE_FEM := $(OUT)/pure-fem/particles_final.h5
PURE_MPM := $(OUT)/pure-mpm/mpm_final.h5
# The runs every sweep and main job compares against; a case without a failure stage
# (geostatic-4x4) has no pure-FE run.
ifeq ($(FEM_END),0)
  PURE_RUNS := $(PURE_MPM)
else
  PURE_RUNS := $(PURE_MPM) $(PURE_FEM)
endif
run_file = $(OUT)/tt$(1)/mpm_final.h5
MAIN_RUNS := $(call run_file,0) $(call run_file,$(MAIN_TT)) $(PURE_RUNS)

.PHONY: all main fem transfer mpm pure-mpm pure-fem fos sweep sweep-plan report clean help
.DELETE_ON_ERROR:
# The particles of a run are made by the pattern rule below on the way to its MPM run;
# they stay when that run is done. (Not .SECONDARY: with no names: that makes every file
# intermediate, so that a missing run was not remade once the report was newer.)
.PRECIOUS: $(OUT)/tt%/particles.h5

all: main

help::
	@sed -n '/^#   make  /,/^# Every run/{/^# Every run/d;s/^# \{0,1\}//;p;}' $(PIPELINE_MK)

# --------------------------------------------------------------------------- stages
# --checkpoint-at-zone-exit: the state at the last output inside the recommended
# transfer zone is written too (fem_t1.300.h5 for column-short), so that the transfer
# time the report recommends can be run with `make mpm TT=1.3`.
fem: $(FEM_DONE)
$(FEM_DONE): $(CASE_INPUTS) $(FEM_SOLVE)
	$(FEM_SOLVE) $(CASE) -o $(OUT)/fem --checkpoint-at-zone-exit --tag fem $(FEM_FLAGS)

# TT names the folder (tt1.3) and, with three decimals, the FE checkpoint (fem_t1.300.h5).
transfer: $(OUT)/tt$(RUN_TT)/particles.h5
$(OUT)/tt%/particles.h5: $(FEM_DONE) $(FEM2MPM)
	@test -f $(OUT)/fem/fem_t$(call three_decimals,$*).h5 || { \
	  echo "no FE checkpoint at t_T = $* s ($(OUT)/fem/fem_t$(call three_decimals,$*).h5); the FE phase wrote t_T =" \
	    $$(ls $(OUT)/fem | sed -n 's/^fem_t\(.*\)\.h5$$/\1/p' | sort -g | awk '{ printf "%g ", $$1 }') >&2; \
	  exit 1; }
	$(FEM2MPM) $(OUT)/fem/fem_t$(call three_decimals,$*).h5 -o $@ --case $(CASE) --tag tt$* \
	  $(ALLOW_INVERTED) $(TRANSFER_FLAGS)

# The main job transfers at t_T ≈ τc as the study prescribes, even where the toe
# elements have begun to fold (column-short: J_min = -0.004 at 2 s); their particles
# get the elements' reference volumes and the transfer report lists them. Sweeps only
# use checkpoints with (|J_t|/|J_0|)_min > 0 (docs/method.md §7).
$(OUT)/tt$(MAIN_TT)/particles.h5: ALLOW_INVERTED := --allow-inverted

mpm: $(call run_file,$(RUN_TT))
$(OUT)/tt%/mpm_final.h5: $(OUT)/tt%/particles.h5 $(MPM_SOLVE)
	$(MPIRUN) $(MPM_SOLVE) $(CASE) -o $(OUT)/tt$* --particles $< --tag tt$* $(MPM_OPTIONS) \
	  $(MPM_FLAGS)

pure-mpm: $(PURE_MPM)
$(PURE_MPM): $(CASE_INPUTS) $(MPM_SOLVE)
	$(MPIRUN) $(MPM_SOLVE) $(CASE) -o $(OUT)/pure-mpm --tag pure-mpm $(MPM_OPTIONS) $(MPM_FLAGS)

# Pure FE: the FE model run on to the MPM end time, measured through the same
# particles (element-wise transfer of its final state, folded elements included:
# small strain runs on through inversion) as the MPM runs. Nothing to do for a case
# without a failure stage.
pure-fem: $(filter $(PURE_FEM),$(PURE_RUNS))
$(PURE_FEM): $(CASE_INPUTS) $(FEM_SOLVE) $(FEM2MPM)
	$(FEM_SOLVE) $(CASE) -o $(OUT)/pure-fem --until $(MPM_END) --no-vtk --tag pure-fem $(FEM_FLAGS)
	$(FEM2MPM) $(OUT)/pure-fem/fem_t$(call three_decimals,$(MPM_END)).h5 -o $@ \
	  --case $(CASE) --stress-interpolation element --allow-inverted --quiet

# --------------------------------------------------------------------------- fos
# The factor of safety by strength reduction (docs/method.md §3): fem-solve's trials in
# out/fos/F<factor>/ and their table in out/fos/strength_reduction.txt, which the report
# sets beside Bishop's (tools/limit_equilibrium.py). Not part of main or sweep: run
# `make fos report`.
FOS := $(OUT)/fos/strength_reduction.txt
fos: $(FOS)
$(FOS): $(CASE_INPUTS) $(FEM_SOLVE) | $(OUT_STAMP)
	$(FEM_SOLVE) $(CASE) -o $(OUT)/fos --strength-reduction --tag fos $(FEM_FLAGS)

# --------------------------------------------------------------------------- sweep
# The valid transfer times are known only once the FE phase has run (the mesh must
# not have entangled), so `sweep` runs the FE phase, then a second make with them as
# TTS, whose sweep.csv depends on those runs and the pure runs.
sweep_times = $$($(METRICS) transfer-times $(CASE) $(OUT)/fem/fem_history.csv)
sweep: fem
	+$(MAKE) -f $(firstword $(MAKEFILE_LIST)) $(OUT)/sweep.csv OUT=$(OUT) SWEEPING=yes \
	  TTS="$(sweep_times)"

sweep-plan: fem
	@for t in $(sweep_times); do printf 'tt%s ' $$t; done; \
	  echo $(patsubst $(OUT)/%/,%,$(dir $(PURE_RUNS)))

# --------------------------------------------------------------------------- metrics
# sweep.csv measures every finished run in OUT/ (slide-metrics sweep), so it depends
# on all of them, on their histories (KE/PE0 peaks) and on the runs the goals ask for:
# the main job's with `make main`, the sweep's with the TTS of `make sweep`, tt$(TT)
# with `make mpm`, the pure runs with `make pure-mpm` or `make pure-fem`.
goals := $(or $(MAKECMDGOALS),main)
WANTED_RUNS :=
ifneq ($(filter main all,$(goals)),)
  WANTED_RUNS += $(MAIN_RUNS)
endif
ifeq ($(SWEEPING),yes)
  WANTED_RUNS += $(foreach t,$(TTS),$(call run_file,$(t))) $(PURE_RUNS)
endif
# `make mpm TT=1.3 report` and the like: the run asked for is measured too.
WANTED_RUNS += $(if $(filter mpm,$(goals)),$(call run_file,$(RUN_TT))) \
               $(if $(filter pure-mpm,$(goals)),$(PURE_MPM)) \
               $(if $(filter pure-fem,$(goals)),$(filter $(PURE_FEM),$(PURE_RUNS)))
MEASURED  := $(sort $(WANTED_RUNS) $(wildcard $(OUT)/tt*/mpm_final.h5 $(PURE_RUNS)))
HISTORIES := $(wildcard $(OUT)/fem/fem_history.csv $(OUT)/*/mpm_history.csv \
                        $(OUT)/pure-fem/fem_history.csv)
SWEEP_CSV := $(OUT)/sweep.csv
FIGURES   := $(OUT)/report/figures.txt
REPORT    := $(OUT)/report/report.md

ifneq ($(filter sweep,$(goals)),)
# `make sweep report`: the sweep's own make measures its runs and writes sweep.csv;
# this make only waits for it (two makes building the same run at once under -j2
# would collide).
$(SWEEP_CSV): | sweep
	@:
else
$(SWEEP_CSV): $(MEASURED) $(HISTORIES) $(CASE) $(METRICS)
	@ls -d $(OUT)/tt*/mpm_final.h5 $(PURE_RUNS) 2> /dev/null | grep -q . || { \
	  echo "no finished run in $(OUT) yet: run 'make sweep' or 'make main' first" >&2; exit 1; }
	$(METRICS) sweep $(CASE) $(OUT)
endif

# --------------------------------------------------------------------------- report
# The report's σyy figure shows the main transfer's particles at t_T, 0.5 s later and at
# the end. The MPM runs keep checkpoints only every mpm.checkpoint_every (2 s), so the
# state at t_T + 0.5 s comes from a second, short run from the same particles that stops
# there (--until) and leaves it as its mpm_final.h5: the same particles, threads and
# output times (which the steps land on) as the main run, so the same first steps, for
# about 0.5/18 of that run's cost (column-short). Made only when the main transfer's run
# is measured; slide-metrics and plots.py do not take the folder for a run.
AFTER_MAIN := $(OUT)/tt$(MAIN_TT)/after-0.5s/mpm_final.h5
$(AFTER_MAIN): $(OUT)/tt$(MAIN_TT)/particles.h5 $(MPM_SOLVE)
	$(MPIRUN) $(MPM_SOLVE) $(CASE) -o $(dir $@) --particles $< --tag tt$(MAIN_TT)-after-0.5s \
	  --until $$(awk 'BEGIN { print $(MAIN_TT) + 0.5 }') --no-vtk --quiet \
	  $(if $(mpm_threads),--threads $(mpm_threads)) $(MPM_FLAGS)
SNAPSHOT_RUNS := $(if $(filter $(call run_file,$(MAIN_TT)),$(MEASURED)),$(AFTER_MAIN))

# plots.py writes the PNGs, then report/figures.txt listing them; report.py reads the
# tables, the FE history and the PNGs.
$(FIGURES): $(SWEEP_CSV) $(HISTORIES) $(CASE) $(TOOLS)/plots.py $(SNAPSHOT_RUNS)
	$(PYTHON) $(TOOLS)/plots.py $(CASE) $(OUT)

$(REPORT): $(SWEEP_CSV) $(FIGURES) $(wildcard $(OUT)/report/*.png) $(HISTORIES) $(CASE) \
           $(TOOLS)/report.py $(wildcard $(FOS)) $(if $(filter fos,$(goals)),$(FOS))
	$(PYTHON) $(TOOLS)/report.py $(CASE) $(OUT)

report: $(REPORT)

main: $(REPORT)

# What the pipeline makes in OUT (and OUT, when nothing else is left there).
clean:
	$(CLEAN) $(OUT) 'case.mk*' fem 'tt*' pure-mpm pure-fem fos 'sweep.csv*' 'sweep.md*' \
	  'profiles.csv*' report
