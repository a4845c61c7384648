#!/usr/bin/env bash
# The FE-life study of fem/README.md ("How long the FE mesh lives"): one column case run
# with the case's own settings except the element's stabilisation or kinematics, each to
# UNTIL seconds (default 6) with a checkpoint every 0.1 s. Prints one Markdown table row
# per variant: the first output time with an inverted element (det J < 0 at a corner or
# zero area, what fem2mpm refuses), the first time an inverted element has a node more
# than 0.1 m above the base (inverted inside the body, not pressed flat onto the ground),
# and the exit from the recommended transfer zone.
#
#   tools/fem-life.sh BUILD_DIR CASE_NAME [OUT_DIR]     e.g. tools/fem-life.sh build column-short
#
# Variants: quad4-1gp with hourglass_coefficient 0.25, 0.2596, 1 (the case), 1.0384, 2
# and 4 (on the columns' square elements 0.2596 and 1.0384 are exactly the assumed-strain
# stabilisations, see fem/README.md), quad4-2x2, and updated-Lagrangian kinematics.
# About 10 s per variant on 2 cores.
set -euo pipefail
[[ $# -ge 2 ]] || { sed -n '2,14s/^# \{0,1\}//p' "$0" >&2; exit 2; }
bin=$(cd "$1" && pwd)/bin
case_name=$2
source=$(cd "$(dirname "$0")/.." && pwd)
case_file=$source/cases/$case_name/case.toml
out=${3:-$(mktemp -d)}
until=${UNTIL:-6}
mkdir -p "$out"

# The first checkpoint time (fem_t<t>.h5, every 0.1 s) with an inverted element that has
# a node above y = 0.1 m; "never" if none by the end.
first_inverted_in_body() {
  /usr/bin/python3 - "$1" <<'EOF'
import glob, re, sys
import h5py
import numpy as np
times = sorted((float(re.search(r"fem_t([0-9.]+)\.h5$", f).group(1)), f)
               for f in glob.glob(sys.argv[1] + "/fem_t*.h5"))
for t, name in times:
    with h5py.File(name, "r") as f:
        inverted = f["elements/scaled_jacobian"][:] < 0.0
        top = f["nodes/coordinates"][:, 1][f["elements/connectivity"][:]].max(axis=1)
    if np.any(inverted & (top > 0.1)):
        print(f"{t:.1f} s")
        break
else:
    print("never")
EOF
}

echo "| variant | first inversion | first inversion inside the body | zone exit |"
echo "|---|---|---|---|"
run_variant() {  # NAME EXTRA_FEM_KEY FEM_SOLVE_ARGS...
  local name=$1 key=$2
  shift 2
  local run=$out/$name
  mkdir -p "$run"
  if [[ -n $key ]]; then
    sed -e "s/^\[fem\]$/[fem]\n$key/" "$case_file" > "$run/case.toml"
  else
    cp "$case_file" "$run/case.toml"
  fi
  "$bin/fem-solve" "$run/case.toml" -o "$run" --until "$until" --checkpoint-every 0.1 \
    --no-vtk --quiet "$@" > "$run/log.txt" 2>&1 || true
  local summary=$run/fem_summary.txt
  value() { sed -n "s/^$1 = //p" "$summary" 2>/dev/null; }
  seconds() { [[ $1 =~ ^[0-9.]+$ ]] && printf '%.1f s' "$1" || echo never; }
  printf '| %s | %s | %s | %s |\n' "$name" "$(seconds "$(value first_time_inverted)")" \
    "$(first_inverted_in_body "$run")" "$(seconds "$(value zone_exit_time)")"
}
for k in 0.25 0.2596 1 1.0384 2 4; do
  run_variant "quad4-1gp, hourglass × $k" "hourglass_coefficient = $k"
done
run_variant "quad4-2x2" "" --element quad4-2x2
run_variant "updated Lagrangian" "" --kinematics updated-lagrangian
