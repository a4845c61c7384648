#!/usr/bin/env bash
# mpm-solve's recorders on 1, 2 and 3 ranks (tests/mpi/README.md): the template's pure
# MPM run to 2 s follows the same particles (the same header: each point's particle is
# chosen from every rank's particles, the lowest id among equals) and records the same
# rows, their values within 1e-6 of each quantity's range (the ranks sum in another
# order: round-off, about 1e-9, grows over the 760 steps).
# Usage: recorders_test.sh BIN_DIR SOURCE_DIR WORK_DIR PYTHON MPIEXEC
set -euo pipefail
bin=$1 src=$2 work=$3 python=$4 mpiexec=$5
case_file=$src/cases/template/case.toml
rm -rf "$work" && mkdir -p "$work"
for n in 1 2 3; do
  "$mpiexec" -n "$n" "$bin/mpm-solve" "$case_file" -o "$work/np$n" --until 2 --threads 1 \
    --no-vtk -q > /dev/null
done
PYTHONPATH=$src/tools "$python" - "$work" <<'PY'
import sys, pathlib
import numpy as np
import slide
work, failed = pathlib.Path(sys.argv[1]), False
for name in ("crest", "toe"):
    one = slide.read_table(work / "np1" / "recorders" / f"{name}.csv")
    for n in (2, 3):
        other = slide.read_table(work / f"np{n}" / "recorders" / f"{name}.csv")
        if list(one) != list(other) or len(one["time"]) != len(other["time"]):
            print(f"{name}, {n} ranks: other columns or rows: {list(other)[:3]}…")
            failed = True
            continue
        worst = max(np.max(np.abs(one[k] - other[k])) / max(np.ptp(one[k]), 1e-12) for k in one)
        print(f"{name}, {n} ranks: {list(one)[1].split('_')[0]}, {len(one['time'])} rows, "
              f"largest difference {worst:.2g} of a column's range")
        failed |= not worst <= 1e-6
sys.exit(1 if failed else 0)
PY
