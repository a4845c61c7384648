#!/usr/bin/env bash
# column-short from its geometry over its whole 20 s on 1, 2 and 3 ranks
# (tests/mpi/README.md): granular flow is chaotic, so after thousands of steps the runs
# are compared by what users measure, runout and crest height (slide-metrics measure),
# within 0.5 % (METHOD §9), and the particles' total mass exactly.
# Usage: full_run_test.sh BIN_DIR SOURCE_DIR WORK_DIR PYTHON MPIEXEC
set -euo pipefail
bin=$1 src=$2 work=$3 python=$4 mpiexec=$5
case_file=$src/cases/column-short/case.toml
rm -rf "$work" && mkdir -p "$work"
for n in 1 2 3; do
  "$mpiexec" -n "$n" "$bin/mpm-solve" "$case_file" -o "$work/np$n" --threads 1 --no-vtk -q
  "$bin/slide-metrics" measure "$case_file" "$work/np$n/mpm_final.h5" | head -1 > "$work/np$n.metrics"
  echo "$n rank(s): $(cat "$work/np$n.metrics")"
done
"$python" - "$work" <<'EOF2'
import sys, pathlib, h5py, numpy as np
work = pathlib.Path(sys.argv[1])
def metrics(n):
    line = (work / f"np{n}.metrics").read_text().split()
    return {k: float(v) for k, v in (item.split("=") for item in line)}
def masses(n):
    with h5py.File(work / f"np{n}" / "mpm_final.h5", "r") as f:
        ids, m = f["particles/id"][:], f["particles/mass"][:]
    return m[np.argsort(ids)]
base, failed = metrics(1), False
for n in (2, 3):
    for key in ("runout", "crest_height"):
        rel = metrics(n)[key] / base[key] - 1
        ok = abs(rel) <= 0.005
        failed |= not ok
        print(f"{n} ranks: {key} {metrics(n)[key]:.4f} m, {100 * rel:+.4f} % of 1 rank's"
              f"{'' if ok else ' (more than 0.5 %)'}")
    if not np.array_equal(masses(1), masses(n)):
        print(f"{n} ranks: the particle masses differ"); failed = True
sys.exit(1 if failed else 0)
EOF2
