#!/usr/bin/env bash
# The Make pipeline on the geostatic-4x4 case (seconds): `make` with no target is `make
# main`, which produces the files of docs/contract.md and the report; a second `make` reruns
# nothing (`make -q` agrees); a newer MPM output re-measures and rewrites the report; a
# missing run is remade although the report is newer; a transfer time that is not a
# number, or has no FE checkpoint, is a one-line error; TT=0 and TT=0.0 are one run; a
# relative OUT is the caller's; a newer MPM program reruns the MPM stages but not the FE
# phase or the transfer; `make help` and `make -C cases help` list targets and
# variables; a Gmsh case's runs depend on its .msh; and `make -j2 sweep report` works
# from an empty folder.
#
#   pipeline_test.sh SOURCE_DIR BUILD_DIR WORK_DIR
set -euo pipefail
source=$1 build=$2 work=$3
rm -rf "$work" && mkdir -p "$work/bin"
# Copies of the programs, so that making one look rebuilt leaves the build alone.
cp -p "$build"/bin/{fem-solve,fem2mpm,mpm-solve,slide-metrics} "$work/bin/"
run_make() { make -C "$source/cases/geostatic-4x4" OUT="$work/out" BIN="$work/bin" "$@"; }
fail() { echo "pipeline_test: $*" >&2; exit 1; }

run_make > "$work/first.log" 2>&1 || { cat "$work/first.log"; fail "make (no target) failed"; }
for f in fem/fem_t0.000.h5 fem/fem_history.csv tt0/particles.h5 tt0/mpm_final.h5 \
         tt0/mpm_history.csv pure-mpm/mpm_final.h5 sweep.csv report/report.md \
         report/geostatic_transfer_error.png; do
  [[ -s $work/out/$f ]] || fail "make (no target) did not write $f"
done
# The columns of docs/contract.md first and in order; slide-metrics may add columns after them.
head -1 "$work/out/sweep.csv" | grep -q '^run,tt,tt_over_tauc,runout,runout_normalised,runout_normalised_error,crest_height,crest_height_error,rmse,jacobian_ratio_min,jacobian_ratio_avg,eps_q_avg\(,\|$\)' \
  || fail "sweep.csv header differs from docs/contract.md"

# Up to date: `make -q` finds nothing to do and a second `make main` runs nothing at all
# (no program, no re-measuring, no plots, no report).
run_make -q main > /dev/null || fail "make -q main: not up to date right after make main"
run_make main > "$work/second.log" 2>&1 || fail "second make main failed"
if grep -E 'bin/(fem-solve|fem2mpm|mpm-solve|slide-metrics) |plots.py|report.py' "$work/second.log"; then
  fail "an up-to-date stage was rerun"
fi

# A newer MPM output (here its history, which gives the KE/PE0 peak): the table, the
# plots and the report are made again, no program runs.
report_before=$(stat -c %Y.%N "$work/out/report/report.md")
touch "$work/out/tt0/mpm_history.csv"  # now: newer than the report written before
run_make -q report > /dev/null && fail "make -q report: up to date although an MPM history is newer"
run_make report > "$work/touched.log" 2>&1 || { cat "$work/touched.log"; fail "make report failed"; }
grep -q 'bin/slide-metrics sweep ' "$work/touched.log" || fail "sweep.csv not re-measured"
grep -q 'plots.py' "$work/touched.log" || fail "plots not redrawn"
grep -q 'report.py' "$work/touched.log" || fail "report not rewritten"
if grep -E 'bin/(fem-solve|fem2mpm|mpm-solve) ' "$work/touched.log"; then
  fail "a program was rerun for a newer history"
fi
[[ $(stat -c %Y.%N "$work/out/report/report.md") != "$report_before" ]] || fail "report.md not rewritten"
run_make -q main > /dev/null || fail "make -q main: not up to date after make report"

# A missing run is remade, although the report and sweep.csv are newer than everything.
rm -r "$work/out/pure-mpm"
run_make main > "$work/missing.log" 2>&1 || { cat "$work/missing.log"; fail "make main failed"; }
grep -q "bin/mpm-solve .* -o $work/out/pure-mpm" "$work/missing.log" || fail "a missing run was not remade"
[[ -s $work/out/pure-mpm/mpm_final.h5 ]] || fail "make main did not remake pure-mpm/mpm_final.h5"
run_make -q main > /dev/null || fail "make -q main: not up to date after remaking a missing run"

# TT: not a number is one line before anything runs; its spellings are one run.
if run_make mpm TT=abc > "$work/tt-abc.log" 2>&1; then fail "make mpm TT=abc succeeded"; fi
[[ $(grep -c '\*\*\*' "$work/tt-abc.log") == 1 ]] && grep -q 'TT=abc is not a transfer time' "$work/tt-abc.log" \
  || { cat "$work/tt-abc.log"; fail "no one-line error for TT=abc"; }
[[ ! -e $work/out/ttabc ]] || fail "make mpm TT=abc made out/ttabc"
for spelling in 0.0 0.000 00 0.0001; do
  run_make -q mpm TT=$spelling > /dev/null || fail "make -q mpm TT=$spelling: not the run tt0"
done
[[ $(find "$work/out" -maxdepth 1 -name 'tt*' | wc -l) == 1 ]] || fail "TT spellings made more than one folder"

# A transfer time without an FE checkpoint: a one-line reason naming the times there are.
if run_make transfer TT=0.5 > "$work/bad-tt.log" 2>&1; then fail "make transfer TT=0.5 succeeded"; fi
[[ $(grep -c '\*\*\*' "$work/bad-tt.log") == 1 ]] &&
  grep -q '\*\*\* no FE checkpoint at t_T = 0.5 s.*the FE phase wrote t_T = 0' "$work/bad-tt.log" \
  || { cat "$work/bad-tt.log"; fail "no one-line error for a missing FE checkpoint"; }

# A stale stage: pretend mpm-solve was rebuilt. The MPM runs rerun, FE and transfer do not.
fem_before=$(stat -c %Y.%N "$work/out/fem/fem_t0.000.h5")
touch -d '+2 seconds' "$work/bin/mpm-solve"
run_make main > "$work/third.log" 2>&1 || fail "make main after touching mpm-solve failed"
grep -q 'bin/mpm-solve ' "$work/third.log" || fail "a stale MPM stage was not rerun"
if grep -E 'bin/(fem-solve|fem2mpm) ' "$work/third.log"; then
  fail "the FE phase or the transfer was rerun although up to date"
fi
[[ $(stat -c %Y.%N "$work/out/fem/fem_t0.000.h5") == "$fem_before" ]] || fail "FE checkpoint rewritten"

# OUT relative to where make is called from (not to the case folder, where -C goes).
mkdir -p "$work/caller"
(cd "$work/caller" && make -C "$source/cases/geostatic-4x4" OUT=relative-out BIN="$work/bin" fem) \
  > "$work/relative.log" 2>&1 || { cat "$work/relative.log"; fail "make fem OUT=relative-out failed"; }
[[ -s $work/caller/relative-out/fem/fem_t0.000.h5 ]] || fail "a relative OUT did not land in the caller's folder"
[[ ! -e $source/cases/geostatic-4x4/relative-out ]] || fail "a relative OUT landed next to case.toml"

# Help: the targets and the variables; the cases' folder has its own.
run_make -s help > "$work/help.txt" || fail "make help failed"
for word in 'make main' 'make sweep' 'TT=' 'OUT=' 'BIN=' 'THREADS=' 'VTK_EVERY='; do
  grep -qF -- "$word" "$work/help.txt" || fail "make help does not list $word"
done
make -s -C "$source/cases" help > "$work/cases-help.txt" || fail "make -C cases help failed"
make -s -C "$source/cases/slope-gmsh" help | grep -q 'make mesh' || fail "slope-gmsh's make help does not list make mesh"
grep -q 'make -C cases validate' "$work/cases-help.txt" || fail "make -C cases help lists no targets"

# A Gmsh case's runs depend on its mesh file: the FE phase and pure MPM list slope.msh
# (Make's database of slope-gmsh's rules; nothing runs).
gmsh_db=$(make -C "$source/cases/slope-gmsh" OUT="$work/out-gmsh" BIN="$work/bin" -pq fem 2> /dev/null || true)
for target in fem/fem_t6.000.h5 pure-mpm/mpm_final.h5; do
  grep -E "^$work/out-gmsh/$target:" <<< "$gmsh_db" | grep -qF "$source/cases/slope-gmsh/slope.msh" ||
    fail "slope-gmsh: $target does not depend on slope.msh"
done

# `make -j2 sweep report` from nothing: the report waits for the sweep's own make.
make -C "$source/cases/geostatic-4x4" OUT="$work/out-sweep" BIN="$work/bin" -j2 sweep report \
  > "$work/sweep.log" 2>&1 || { cat "$work/sweep.log"; fail "make -j2 sweep report failed"; }
for f in sweep.csv report/report.md; do
  [[ -s $work/out-sweep/$f ]] || fail "make -j2 sweep report did not write $f"
done
echo "pipeline_test: main, up-to-date, newer-output, missing-run, TT, relative-OUT, stale-stage, help, mesh-file and sweep-report checks passed"
