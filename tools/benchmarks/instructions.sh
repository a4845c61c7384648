#!/usr/bin/env bash
# Instructions per particle-step of the MPM step loop (with its phase table) or per
# element-step of the FE step loop, under callgrind: for machines whose CPU counter is
# hidden (the benchmarks then say so), and for the tables of mpm/README.md ("Where a
# step's instructions go") and fem/README.md. Instruction counts do not change with the
# machine's load, so they compare across days where seconds do not.
#
#   tools/benchmarks/instructions.sh [mpm] [BUILD] [-- bench_mpm options]
#   tools/benchmarks/instructions.sh fem [BUILD] [ELEMENT MODEL]     (default quad4-1gp mohr-coulomb)
#
# BUILD is a build folder (default build-portable: `cmake -S . -B build-portable
# -DSLIDE_NATIVE=OFF`, the portable x86-64 build the project's figures are quoted for;
# `cmake --build build-portable --target bench_mpm bench_fem`). mpm: bench_mpm on 1
# thread for 20 and for 60 steps after the same untimed start (default --skip 200: the
# column is collapsing), the difference divided by 40 × the particles, so that the set-up
# and the skipped steps cancel (about 1 minute). fem: bench_fem on column-short's failure
# stage with the step loop alone collected (callgrind --toggle-collect), divided by the
# element-steps it prints (10 s to 2 minutes). Needs valgrind (Debian's package).
# KEEP_CALLGRIND=1 keeps the mpm mode's callgrind files (the folder is printed) for
# callgrind_annotate.
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
mode=mpm
[[ ${1-} == mpm || ${1-} == fem ]] && { mode=$1; shift; }
build=${1:-$root/build-portable}
[[ $# -gt 0 ]] && shift
[[ ${1-} == -- ]] && shift
command -v valgrind > /dev/null || { echo "instructions.sh: valgrind is not installed (apt-get install valgrind)" >&2; exit 1; }
# The wait setting given here: the benchmarks would otherwise start themselves again with
# it (prefer_yielding_threads), out of valgrind's sight.
export GOMP_SPINCOUNT=10000 OMP_NUM_THREADS=1
if [[ $mode == fem ]]; then
  bench=$build/tools/benchmarks/fem/bench_fem
  [[ -x $bench ]] || { echo "instructions.sh: no $bench (cmake --build $build --target bench_fem)" >&2; exit 1; }
  element=${1:-quad4-1gp} model=${2:-mohr-coulomb}
  out=$(mktemp)
  trap 'rm -f "$out" "$out.cg"' EXIT
  valgrind --tool=callgrind --callgrind-out-file="$out.cg" \
    "--toggle-collect=slide::fem::ExplicitSolver::step(*" \
    "$bench" "$root/cases/column-short/case.toml" "$element" "$model" > "$out" 2> /dev/null
  total=$(callgrind_annotate "$out.cg" | grep 'PROGRAM TOTALS' | awk '{gsub(",", "", $1); print $1}')
  line=$(grep "elements=" "$out")
  elements=$(grep -o 'elements=[0-9]*' <<< "$line" | cut -d= -f2)
  steps=$(grep -o 'steps=[0-9]*' <<< "$line" | head -1 | cut -d= -f2)
  echo "$element $model: $((total / (elements * steps))) instructions per element-step" \
       "(callgrind, $steps steps of $elements elements)"
  exit 0
fi
bench=$build/tools/benchmarks/mpm/bench_mpm
[[ -x $bench ]] || { echo "instructions.sh: no $bench (cmake --build $build --target bench_mpm)" >&2; exit 1; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
[[ -n ${KEEP_CALLGRIND-} ]] && trap - EXIT && echo "instructions.sh: files in $work" >&2
skip=200
for arg in "$@"; do [[ $arg == --skip=* ]] && skip=${arg#--skip=}; done
for steps in 20 60; do
  valgrind --tool=callgrind --callgrind-out-file="$work/cg.$steps" \
    "$bench" --threads 1 --repeat 1 --skip "$skip" --steps "$steps" "$@" \
    > "$work/out.$steps" 2> "$work/err.$steps" ||
    { cat "$work/err.$steps" >&2; exit 1; }
  callgrind_annotate --inclusive=yes --threshold=100 "$work/cg.$steps" > "$work/annotated.$steps"
done
particles=$(grep -o 'particles=[0-9]*' "$work/out.60" | head -1 | cut -d= -f2)
head -1 "$work/out.60"
/usr/bin/python3 - "$work" "$particles" <<'PY'
import re, sys, pathlib
work, particles = pathlib.Path(sys.argv[1]), int(sys.argv[2])
def costs(steps):
    text = (work / f"annotated.{steps}").read_text()
    total = int(re.search(r"^([\d,]+) \(100.0%\)\s+PROGRAM TOTALS", text, re.M).group(1).replace(",", ""))
    functions = {}
    for line in text.splitlines():
        # "12,345 (1.2%)  file:function(arguments) [object]"; OpenMP's outlined bodies are
        # "[clone ._omp_fn.N]" entries inside their function's inclusive count: skipped.
        m = re.match(r"^\s*([\d,]+) \(\s*[\d.]+%\)\s+[^:\s]*:(.*)$", line)
        if m and "[clone" not in m.group(2):
            name = m.group(2)
            functions[name] = functions.get(name, 0) + int(m.group(1).replace(",", ""))
    return total, functions
(t20, f20), (t60, f60) = costs(20), costs(60)
per = 40.0 * particles
# The solver's phases (mpm_solver.cpp, MpmSolver::step), inclusive of what they call;
# the final pass without the point update, which has its own row.
phases = [("locate (particle check, block bands)", r"^slide::mpm::locate_particles\("),
          ("sort by cell", r"^slide::mpm::sort_particles_by_cell\("),
          ("P2G (mass, momentum, forces into windows)", r"^slide::mpm::particles_to_grid\("),
          ("window sums into the grid", r"^slide::mpm::sum_node_windows\("),
          ("grid update (nodes, boundaries, damping)", r"^slide::mpm::update_nodes\("),
          ("MUSL velocity pass and re-projection", r"^slide::mpm::remap_momenta\("),
          ("MUSL re-projected velocities", r"^slide::mpm::finish_remapped_velocities\("),
          ("final pass G2P (gather, move, smoothing)", r"^slide::mpm::grid_to_particles\("),
          ("  of which the point update (constitutive)", r"update_stress(_pair)?\(")]
def phase(functions, pattern):
    return sum(v for k, v in functions.items() if re.search(pattern, k))
print(f"instructions per particle-step: {(t60 - t20) / per:.0f} "
      f"(callgrind, 60 − 20 steps of {particles} particles)")
print("| phase | instructions per particle-step |")
print("|---|---|")
accounted = 0.0
for label, pattern in phases:
    value = (phase(f60, pattern) - phase(f20, pattern)) / per
    if not label.startswith("  "):
        accounted += value
    print(f"| {label} | {value:.0f} |")
print(f"| the rest of the step | {(t60 - t20) / per - accounted:.0f} |")
PY
