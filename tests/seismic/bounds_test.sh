#!/bin/sh
# Bounded work for every input (docs/method.md §8): a motion record far longer than the
# runs is kept only to their end (the checkpoint and motion.csv hold the run's part, the
# log says so); a recorder cadence of 1e-15 s records at every step and ends; recorders
# that would hold more than 1 GB, and a recorder name longer than a file name takes, are
# refused in one line before the previous run's files are touched; so is a run whose
# checkpoints and frames would be more than a million files.
#   bounds_test.sh BIN SOURCE_DIR WORK_DIR PYTHON
set -eu
bin=$1 src=$2 work=$3 python=$4
rm -rf "$work"
mkdir -p "$work"
block=$src/tests/seismic/sliding-block/case.toml
fail() { echo "FAIL: $*" >&2; exit 1; }

# The sliding block on a 300 s record (two columns, every 0.01 s), its runs 0.2 s long.
"$python" - "$work/long.csv" <<'PY'
import sys, math
with open(sys.argv[1], "w") as f:
    for k in range(30001):
        t = 0.01 * k
        f.write(f"{t:.2f},{0.5 * math.sin(2 * math.pi * 2.0 * t):.6f}\n")
PY
case_with() {  # case_with FILE MOTION RECORDER: the block with another motion and recorder
  "$python" - "$block" "$1" "$2" "$3" <<'PY'
import sys, re
text = open(sys.argv[1]).read()
motion, recorder = sys.argv[3], sys.argv[4]
text = text.replace('end_time = 2.5', 'end_time = 0.2', 1)  # fem's; mpm's stays 2.5
text = text.replace('checkpoint_times = [0.8]', 'checkpoint_times = []')
text = text.replace('sweep_times = [0.0, 0.8]', 'sweep_times = [0.0]')
text = re.sub(r'\[fem\.motion\.horizontal\]\n(?:.+\n)+', motion + '\n', text)
text = re.sub(r'\[\[fem\.recorders\]\]\n(?:.+\n)+', recorder + '\n', text)
open(sys.argv[2], "w").write(text.replace('start_time = 0.2', 'start_time = 0.0'))
PY
}
long_motion='[fem.motion.horizontal]
source = "file"
file = "long.csv"
units = "m/s2"'
recorder='[[fem.recorders]]
name = "block"
points = [[2.0, 0.0]]
every = 0.002'
case_with "$work/case.toml" "$long_motion" "$recorder"
mkdir -p "$work/sliding-block" && mv "$work/case.toml" "$work/sliding-block/case.toml"
cp "$work/long.csv" "$work/sliding-block/"
c=$work/sliding-block/case.toml
"$bin/fem-solve" "$c" -o "$work/long" --no-vtk > "$work/long.log" 2>&1 || { cat "$work/long.log"; fail "long record"; }
grep -q "the record runs to t = 300 s, past the case's runs" "$work/long.log" ||
  fail "no warning of the long record in $work/long.log"
size=$(stat -c %s "$work/long/fem_t0.200.h5")
[ "$size" -lt 2000000 ] || fail "fem_t0.200.h5 is $size bytes for a 0.2 s run"
lines=$(wc -l < "$work/long/motion.csv")
# the mpm.end_time of 2.5 s bounds what is kept: 2.5 s of samples, not 300 s
"$python" - "$work/long/fem_t0.200.h5" "$lines" <<'PY'
import sys, h5py
f = h5py.File(sys.argv[1], "r")
m = f["motion"]
n = m["acceleration"].shape[0]
end = m.attrs["start_time"] + m.attrs["step"] * (n - 1)
if not (2.5 <= end < 2.6):
    sys.exit(f"/motion keeps samples to {end} s (expected the case's last end time, 2.5 s)")
if not (300.0 <= m.attrs["record_end_time"] < 300.0 + m.attrs["step"]):
    sys.exit(f"/motion record_end_time {m.attrs['record_end_time']} (expected 300 s, to a step)")
if abs(int(sys.argv[2]) - 1 - n) > 1:
    sys.exit(f"motion.csv has {sys.argv[2]} lines for {n} samples")
print(f"long record: {n} samples kept to {end:.4f} s of 300 s")
PY

# A recorder every 1e-15 s records at every step and ends.
fine='[[fem.recorders]]
name = "block"
points = [[2.0, 0.0]]
every = 1e-15'
case_with "$c" '[fem.motion.horizontal]
source = "ricker"
units = "g"
amplitude = 0.5
peak_frequency = 2.0
peak_time = 0.6' "$fine"
timeout 120 "$bin/fem-solve" "$c" -o "$work/fine" --no-vtk > "$work/fine.log" 2>&1 ||
  { cat "$work/fine.log"; fail "recorder every 1e-15 s"; }
steps=$(sed -n 's/^summary: steps=\([0-9]*\).*/\1/p' "$work/fine.log")
rows=$(($(wc -l < "$work/fine/recorders/block.csv") - 1))
[ "$rows" -ge $((steps - 1)) ] && [ "$rows" -le $((steps + 2)) ] ||
  fail "recorder every 1e-15 s: $rows rows for $steps steps"
echo "recorder every 1e-15 s: $rows rows, $steps steps"

# Recorders of the base nodes at every step over 300 s are refused before a file is written;
# so is a name of 300 bytes. The previous run's files are left as they were.
before=$(cd "$work/fine" && find . -type f -exec md5sum {} + | sort)
huge='[[fem.recorders]]
name = "all"
node_set = "base"
every = 0.0'
case_with "$c" '[fem.motion.horizontal]
source = "ricker"
units = "g"
amplitude = 0.5
peak_frequency = 2.0
peak_time = 0.6' "$huge"
if "$bin/fem-solve" "$c" -o "$work/fine" --no-vtk --until 300 > "$work/huge.log" 2>&1; then
  fail "recorders of 1 GB accepted"
fi
grep -q "fem.recorders would hold and write about" "$work/huge.log" || { cat "$work/huge.log"; fail "message"; }
[ "$(wc -l < "$work/huge.log")" -le 3 ] || { cat "$work/huge.log"; fail "not one line"; }
long_name=$(printf 'r%.0s' $(seq 300))
case_with "$c" '[fem.motion.horizontal]
source = "ricker"
units = "g"
amplitude = 0.5
peak_frequency = 2.0
peak_time = 0.6' "[[fem.recorders]]
name = \"$long_name\"
points = [[2.0, 0.0]]
every = 0.01"
if "$bin/fem-solve" "$c" -o "$work/fine" --no-vtk > "$work/name.log" 2>&1; then
  fail "a recorder name of 300 bytes accepted"
fi
grep -q "the name has 300 bytes, at most 200" "$work/name.log" || { cat "$work/name.log"; fail "message"; }
after=$(cd "$work/fine" && find . -type f -exec md5sum {} + | sort)
[ "$before" = "$after" ] || fail "a refused run changed the previous run's files"
echo "refused before writing: recorders of > 1 GB, a name of 300 bytes"

# Checkpoints and frames past the disk or a million files: refused before the folder is
# made (common/run/README.md, "A run that would fill the disk").
if "$bin/fem-solve" "$src/cases/geostatic-4x4/case.toml" -o "$work/many" --until 5000 \
  --checkpoint-every 0.001 > "$work/many.log" 2>&1; then
  fail "five million checkpoints accepted"
fi
grep -q "about 5e+06 checkpoints and 5e+06 VTK frames (at most 1e+06 files)" "$work/many.log" ||
  { cat "$work/many.log"; fail "message"; }
[ ! -e "$work/many" ] || fail "a refused run made its folder"
echo "refused before writing: 5e6 checkpoints"
