#!/usr/bin/env bash
# cases/embankment-saturated through its own Makefile, cut to 3 s (1 s of shaking): the
# FE phase with pore water and a reservoir, and the pore-water report.
#
#   pore_water_case_test.sh SOURCE_DIR BIN_DIR PYTHON WORK_DIR
#
# Checks: the geostatic state is the hydrostatic one (r_u = 0 everywhere at t = 0: the
# history's largest r_u and area with r_u ≥ 0.7 are exactly 0), the run reaches 3 s, and
# the report names its largest r_u with its three figures.
set -euo pipefail
source=$1 bin=$2 python=$3 work=$4
rm -rf "$work"
make -C "$source/cases/embankment-saturated" main OUT="$work" BIN="$bin" PYTHON="$python" \
  FEM_FLAGS="--until 3 --no-vtk --quiet" SNAPSHOTS=0,2,3 > "$work.log" 2>&1 ||
  { cat "$work.log"; exit 1; }
awk -F, 'NR == 1 { for (i = 1; i <= NF; i++) c[$i] = i; next }
         NR == 2 { if ($c["pore_pressure_ratio_max"] != 0 || $c["high_pore_pressure_area"] != 0) {
                     print "t = 0: r_u is not 0: " $c["pore_pressure_ratio_max"]; bad = 1 } }
         { last = $c["time"] }
         END { if (last + 0 < 3 - 1e-9) { print "the run stopped at t = " last; bad = 1 }
               exit bad }' "$work/fem/fem_history.csv"
grep -q '^| largest r_u |' "$work/report/report.md"
for figure in pore_water_history pore_water_recorders pore_water_snapshots; do
  test -s "$work/report/$figure.png" || { echo "no $figure.png"; exit 1; }
done
echo "embankment-saturated: hydrostatic at t = 0, ran to 3 s, report written"
