#!/usr/bin/env bash
# Particle-steps per second of this project's MPM and of CB-Geo MPM on the same column,
# side by side, for anyone who has built CB-Geo (github.com/cb-geo/mpm; its `mpm`
# program). The suite never needs CB-Geo; this script is the recipe behind the ratio
# quoted in README.md ("For scale: …", the performance section).
#
#   tools/benchmarks/cbgeo_side_by_side.sh CBGEO_MPM [STEPS] [BUILD]
#
# CBGEO_MPM is CB-Geo's executable; STEPS the steps each code runs (default 1000); BUILD
# this project's build (default build). column-short's column (32,000 particles, 4 × 4
# a cell) starts at rest under K0 stresses (pure MPM's first checkpoint); mpm2cbgeo
# writes CB-Geo's input of the same particles, grid and boundaries (linear ED2Q4, USL,
# FLIP, pressure smoothing: what the exporter writes, tools/interop/README.md) with a
# fixed step; this project runs the same steps of the same length twice, with the case's
# algorithms (uGIMP, MUSL, APIC, cell smoothing) and with the nearest to CB-Geo's
# (linear, USL, FLIP, cell smoothing), with mpm2cbgeo's step (C = 0.05: CB-Geo's fixed
# step must hold as the front expands). All on one thread (OMP_NUM_THREADS=1, TBB's
# too); run it on a quiet machine and alternate rounds: the ratios are what compare
# across days, not the seconds. Where GNU time is installed (/usr/bin/time, Debian's
# `time`), each run's peak memory is printed too.
#
# CB-Geo on Debian 12 (commit 53fcb76 built so in about 3 minutes, without patches):
# apt-get install libboost-filesystem-dev libboost-system-dev (Eigen and HDF5 are the
# project's own dependencies), then in CB-Geo's checkout
#   cmake -B build -DCMAKE_BUILD_TYPE=Release -DMPM_BUILD_TESTING=Off \
#     -DCMAKE_DISABLE_FIND_PACKAGE_MPI=ON -DCMAKE_DISABLE_FIND_PACKAGE_VTK=ON
#   cmake --build build --target mpm
set -euo pipefail
[[ $# -ge 1 ]] || { sed -n '2,27s/^# \{0,1\}//p' "$0" >&2; exit 2; }
cbgeo=$1
steps=${2:-1000}
root=$(cd "$(dirname "$0")/../.." && pwd)
build=${3:-$root/build}
[[ -x $cbgeo ]] || { echo "cbgeo_side_by_side: $cbgeo is not an executable (CB-Geo's mpm)" >&2; exit 1; }
[[ $steps =~ ^[0-9]+$ && $steps -ge 10 ]] || { echo "cbgeo_side_by_side: STEPS must be a whole number ≥ 10" >&2; exit 2; }
for program in mpm-solve mpm2cbgeo; do
  [[ -x $build/bin/$program ]] || { echo "cbgeo_side_by_side: no $build/bin/$program (build the project)" >&2; exit 1; }
done
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
export OMP_NUM_THREADS=1 TBB_NUM_THREADS=1
case_file=$root/cases/column-short/case.toml

# The start: pure MPM's particles at t = 0 (its first checkpoint).
"$build/bin/mpm-solve" "$case_file" -o "$work/start" --until 0.001 --no-vtk -q > /dev/null
# CB-Geo's fixed step (C h / c_p at the particles' density, mpm2cbgeo), then its input of
# STEPS of them.
"$build/bin/mpm2cbgeo" "$case_file" "$work/start/mpm_t0.000.h5" -o "$work/step" -q \
  --end-time 1.0 --output-every 1.0 > /dev/null
dt=$(/usr/bin/python3 -c 'import json, sys; print(json.load(open(sys.argv[1]))["analysis"]["dt"])' "$work/step/mpm.json")
end=$(/usr/bin/python3 -c "print($dt * $steps)")
"$build/bin/mpm2cbgeo" "$case_file" "$work/start/mpm_t0.000.h5" -o "$work/cbgeo" -q \
  --end-time "$end" --output-every "$end" > /dev/null
particles=$(/usr/bin/python3 -c 'import h5py, sys; print(len(h5py.File(sys.argv[1], "r")["particles/id"]))' "$work/start/mpm_t0.000.h5")

measure=()
[[ -x /usr/bin/time ]] && measure=(/usr/bin/time -f %M -o "$work/peak")
seconds() {  # COMMAND...: "wall-seconds peak-MB" of it (peak 0 without GNU time)
  local start end
  echo 0 > "$work/peak"
  start=$(date +%s.%N)
  "${measure[@]}" "$@" > "$work/last.log" 2>&1 || { tail -5 "$work/last.log" >&2; exit 1; }
  end=$(date +%s.%N)
  /usr/bin/python3 -c "print(f'{$end - $start:.3f},{int(open(\"$work/peak\").read().split()[-1]) / 1024:.0f}')"
}
# This project with CB-Geo's step: the case with a fixed time_step and the end after STEPS.
sed -e "s/^time_step = .*//" -e "s/^\[mpm\]$/[mpm]\ntime_step = $dt/" \
    -e "s/^main_time = .*/main_time = 0.0/" -e "s/^sweep_times = .*/sweep_times = [0.0]/" \
    -e "/^\[mpm\]/,/^\[/ s/^end_time = .*/end_time = $end/" "$case_file" > "$work/case.toml"
ours=$(seconds "$build/bin/mpm-solve" "$work/case.toml" -o "$work/ours" --no-vtk -q --threads 1)
# The nearest to CB-Geo's: linear shape functions, USL, FLIP without PIC.
sed -e "s/^velocity_transfer = .*/velocity_transfer = \"flip-pic\"\npic_fraction = 0.0/" \
    "$work/case.toml" > "$work/like.toml"
like=$(seconds "$build/bin/mpm-solve" "$work/like.toml" -o "$work/like" --no-vtk -q --threads 1 \
       --shape-function linear --update-scheme usl)
theirs=$(seconds "$cbgeo" -f "$work/cbgeo/" -i mpm.json)
/usr/bin/python3 - "$particles" "$steps" "$ours" "$like" "$theirs" <<'PY'
import sys
particles, steps = int(sys.argv[1]), int(sys.argv[2])
(ours, ours_mb), (like, like_mb), (theirs, theirs_mb) = (
    (float(v.split(",")[0]), float(v.split(",")[1])) for v in sys.argv[3:6])
rate = lambda s: particles * steps / s / 1e6
memory = lambda mb: f", peak {mb:.0f} MB" if mb > 0 else ""
print(f"column-short, {particles} particles, {steps} steps, 1 thread (wall includes start-up and the last write)")
print(f"this project, case algorithms (uGIMP, MUSL, APIC, cell smoothing): "
      f"{ours:.2f} s, {rate(ours):.2f} M particle-steps/s{memory(ours_mb)}")
print(f"this project, linear, USL, FLIP, cell smoothing:                   "
      f"{like:.2f} s, {rate(like):.2f} M particle-steps/s{memory(like_mb)}")
print(f"CB-Geo MPM (linear ED2Q4, USL, FLIP, pressure smoothing):          "
      f"{theirs:.2f} s, {rate(theirs):.2f} M particle-steps/s{memory(theirs_mb)}")
print(f"ratio, case algorithms / CB-Geo: {theirs / ours:.1f}×; like for like: {theirs / like:.1f}×")
PY
