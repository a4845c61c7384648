#!/usr/bin/env bash
# cases/liquefiable-deposit through its own Makefile, cut to 12 s (the 8 s of shaking and
# 3 s after): a level deposit of loose sand (PM4Sand, D_R = 0.40, h_po calibrated at the
# start) that liquefies, the element tests of its sand, and the reports.
#
#   liquefaction_case_test.sh SOURCE_DIR BIN_DIR PYTHON WORK_DIR
#
# Checks, each of which could fail (docs/method.md §10):
#  - the element test at the site's CSR (0.19, 1.9 times the CRR of 0.100) reaches
#    r_u ≥ 0.95 within the 16 cycles of the shaking, so the column must liquefy: every
#    recorded depth from 2.75 m to 9.75 m reaches r_u ≥ 0.95 before the shaking ends;
#  - the calibration of the case's sand gives 15 ± 1 cycles at its CRR;
#  - after the shaking the excess pore pressure dissipates from the undrained base up:
#    at 9.75 m r_u at 12 s is below its largest by more than 0.05;
#  - r_u never exceeds 1 (p′ stays positive) and the surface settles;
#  - a restart from the 5 s checkpoint reproduces the 6 s one bit for bit (stress, pore
#    pressure and PM4Sand's state records), in the liquefied state;
#  - fem2mpm carries each element's PM4Sand records to its particles unchanged (element
#    interpolation);
#  - the sloping column (sloping.toml, 3°, sides tied in the geostatic stage) starts with
#    the infinite slope's static shear τ = ρ_sat g z sin 3° (to 1e-6 of ρ g H) and spreads
#    downslope during the shaking, its surface moving on (+x) and never back by more than
#    a tenth of what it gained.
set -euo pipefail
source=$1 bin=$2 python=$3 work=$4
rm -rf "$work"
make -C "$source/cases/liquefiable-deposit" main OUT="$work" BIN="$bin" PYTHON="$python" \
  FEM_FLAGS="--until 12 --no-vtk --quiet" SNAPSHOTS=1,3,9,12 > "$work.log" 2>&1 ||
  { cat "$work.log"; exit 1; }
"$python" - "$work" <<'PY'
import csv, sys
work = sys.argv[1]
def rows(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))
calibration = dict(line.strip().split(" = ") for line in open(f"{work}/element/calibration/calibration.txt"))
cycles = float(calibration["cycles_at_contraction_rate"])
assert abs(cycles - 15.0) <= 1.0, f"calibration: {cycles} cycles at the CRR"
element = rows(f"{work}/element/site_csr.csv")
n95 = next((float(r["cycles"]) for r in element if float(r["pore_pressure_ratio"]) >= 0.95), None)
assert n95 is not None and n95 < 16.0, f"element test at the site CSR: r_u 0.95 after {n95} cycles"
water = rows(f"{work}/fem/recorders/water.csv")
ru = [k for k in water[0] if k.endswith("_ru")]
depths = [0.75 + i for i in range(len(ru))]
start, end = 1.0, 9.0
bad = []
for depth, key in zip(depths, ru):
    values = [(float(r["time"]), float(r[key])) for r in water]
    assert max(v for _, v in values) <= 1.0, f"{depth} m: r_u above 1"
    if depth >= 2.7:
        first = next((t for t, v in values if v >= 0.95), None)
        if first is None or first > end:
            bad.append(f"{depth} m: r_u 0.95 at {first}")
        print(f"{depth:5.2f} m: r_u ≥ 0.95 at t = {first:.2f} s ({2.0 * (first - start):.1f} cycles); largest {max(v for _, v in values):.3f}")
assert not bad, "; ".join(bad)
base = [float(r[ru[-1]]) for r in water]
assert base[-1] < max(base) - 0.05, f"9.75 m: r_u {base[-1]:.3f} at 12 s, largest {max(base):.3f}: no dissipation"
surface = rows(f"{work}/fem/recorders/surface.csv")
uy = next(k for k in surface[0] if k.endswith("_uy_rel"))
assert float(surface[-1][uy]) < 0.0, "the surface did not settle"
print(f"element test at CSR 0.19: r_u 0.95 after {n95:.2f} cycles; calibration {cycles:.2f} cycles; "
      f"base r_u {max(base):.3f} -> {base[-1]:.3f}; settlement {-1000 * float(surface[-1][uy]):.1f} mm")
PY
"$bin/fem-solve" "$source/cases/liquefiable-deposit/case.toml" -o "$work/restart" \
  --restart "$work/fem/fem_t5.000.h5" --until 6 --no-vtk --quiet
"$python" - "$work/fem/fem_t6.000.h5" "$work/restart/fem_t6.000.h5" <<'PY'
import sys, h5py, numpy
a, b = (h5py.File(p, "r") for p in sys.argv[1:3])
for name in ("gauss_points/stress", "gauss_points/state/surface_stress", "elements/pore_pressure",
             "nodes/velocity"):
    assert numpy.array_equal(a[name][()], b[name][()]), f"restart: {name} differs"
records = a["gauss_points/state/surface_stress"][()]
assert records.shape[1] == 40 and (records[:, 38] > 0).all(), "PM4Sand records: not switched"
print("restart from 5 s: the 6 s checkpoint bit for bit")
PY
"$bin/fem2mpm" "$work/fem/fem_t12.000.h5" -o "$work/particles.h5" \
  --case "$source/cases/liquefiable-deposit/case.toml" --quiet
"$python" - "$work/fem/fem_t12.000.h5" "$work/particles.h5" <<'PY'
import sys, h5py, numpy
fem, particles = (h5py.File(p, "r") for p in sys.argv[1:3])
gauss = fem["gauss_points/state/surface_stress"][()]
carried = particles["particles/state/surface_stress"][()]
element = particles["particles/element"][()]
assert numpy.array_equal(carried, gauss[element]), "transfer: PM4Sand records changed"
print(f"transfer: {len(carried)} particles carry their element's PM4Sand records")
PY
"$python" - "$work/sloping" <<'PY'
import csv, math, sys, h5py, numpy
work = sys.argv[1]
start = h5py.File(f"{work}/fem/fem_t0.000.h5", "r")
stress = start["gauss_points/stress"][()]
y = start["gauss_points/coordinates"][()][:, 1]
rho_g = 1950.0 * 9.81
error = numpy.abs(stress[:, 3] - rho_g * math.sin(math.radians(3.0)) * (10.0 - y)).max()
assert error < 1e-6 * rho_g * 10.0, f"sloping: static shear off by {error:.3g} Pa"
with open(f"{work}/fem/recorders/surface.csv", newline="") as f:
    rows = list(csv.DictReader(f))
ux = next(k for k in rows[0] if k.endswith("_ux_rel"))
series = [(float(r["time"]), float(r[ux])) for r in rows]
at_start = min(series, key=lambda p: abs(p[0] - 1.0))[1]
end = series[-1][1] - at_start
peak = max(u for _, u in series) - at_start
assert end > 0.05 and end > 0.9 * peak, f"sloping: lateral {end:.3f} m at the end, largest {peak:.3f} m"
print(f"sloping: static shear exact to {error:.2e} Pa; lateral spread {1000 * end:.0f} mm by t = {series[-1][0]:g} s")
PY
grep -q '^| depth (m) |' "$work/report/liquefaction.md"
grep -q '^| depth (m) |' "$work/sloping/report/liquefaction.md"
for figure in report/liquefaction_ru report/liquefaction_profiles report/pore_water_snapshots element/element element/crr_curve; do
  test -s "$work/$figure.png" || { echo "no $figure.png"; exit 1; }
done
echo "liquefiable-deposit: liquefied from 2.75 m down during the shaking, dissipating after"
