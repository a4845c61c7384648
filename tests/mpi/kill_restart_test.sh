#!/usr/bin/env bash
# kill -9 of an MPI run at random moments, and its restart bit for bit (tests/mpi/README.md):
# column-short from its geometry on 2 ranks to 1.2 s, a checkpoint every 0.2 s. The
# reference runs uninterrupted; each trial kills every process of a run (mpirun and both
# ranks) with SIGKILL at a moment drawn from a seeded generator, then restarts from the
# last checkpoint the killed run left (or runs again from the start into its folder when
# it had none), on 2 ranks again. The restart's mpm_final.h5 must be the reference's
# particle by particle, bit for bit (compare_by_id.py, tolerance 0): each rank takes back
# the rows it held (/solver slab_cuts and slab_rows, docs/parallel.md); the killed run's
# folder must hold only whole checkpoints (its temporaries and lock are cleaned or taken
# over by the restart, which says so). Then restarts from each of the reference's own
# checkpoints (0.2 … 1.0 s) must end bit for bit too, wherever the kills landed.
#   kill_restart_test.sh BIN_DIR SOURCE_DIR WORK_DIR PYTHON MPIEXEC [SEED]
set -uo pipefail
bin=$1 src=$2 work=$3 python=$4 mpiexec=$5 seed=${6:-31}
rm -rf "$work"
mkdir -p "$work"
case_file=$work/case.toml
sed -e 's/^checkpoint_every = 2.0 .*/checkpoint_every = 0.2/' \
  "$src/cases/column-short/case.toml" > "$case_file"
grep -q '^checkpoint_every = 0.2$' "$case_file" || { echo "FAIL: could not set the cadence" >&2; exit 1; }
status=0
run() {  # run OUT [options]: 2 ranks
  local out=$1
  shift
  "$mpiexec" -q -n 2 "$bin/mpm-solve" "$case_file" -o "$work/$out" --threads 1 -q --no-vtk \
    --until 1.2 "$@"
}

start=$(date +%s%N)
run reference > /dev/null 2> "$work/reference.err" || { cat "$work/reference.err" >&2; exit 1; }
wall_ms=$((($(date +%s%N) - start) / 1000000))
echo "reference: 2 ranks to 1.2 s in ${wall_ms} ms"

RANDOM=$seed
for trial in 1 2 3; do
  delay_ms=$((wall_ms / 10 + RANDOM % (wall_ms * 8 / 10)))
  out=killed-$trial
  run "$out" > /dev/null 2> "$work/$out.err" &
  launcher=$!
  sleep "$(printf '%d.%03d' $((delay_ms / 1000)) $((delay_ms % 1000)))"
  pkill -KILL -f -- "-o $work/$out " 2> /dev/null
  kill -KILL $launcher 2> /dev/null
  wait $launcher 2> /dev/null
  # The last checkpoint before the end time: on a loaded machine the kill may land after
  # the run wrote its final one (mpm_t1.200.h5), from which there is nothing to continue.
  last=$(ls "$work/$out"/mpm_t*.h5 2> /dev/null | grep -v 'mpm_t1\.200\.h5$' | sort | tail -1)
  left=$(ls -A "$work/$out" 2> /dev/null | grep -c 'tmp-\|slide-lock')
  if [[ -z $last ]]; then  # killed before its first checkpoint: run again into the folder
    run "$out" > /dev/null 2> "$work/$out.restart.err"
  else
    run "$out" --restart "$last" > /dev/null 2> "$work/$out.restart.err"
  fi
  code=$?
  if [[ $code -ne 0 ]]; then
    echo "FAIL: trial $trial: the restart from $last ended with status $code:" >&2
    cat "$work/$out.restart.err" >&2
    status=1
    continue
  fi
  if ! "$python" "$src/tests/mpi/compare_by_id.py" "$work/reference/mpm_final.h5" \
    "$work/$out/mpm_final.h5" 0 > "$work/$out.compare" 2>&1; then
    echo "FAIL: trial $trial: the restart from $last is not the reference bit for bit:" >&2
    cat "$work/$out.compare" >&2
    status=1
    continue
  fi
  if ls -A "$work/$out" | grep -q 'tmp-\|slide-lock'; then
    echo "FAIL: trial $trial: the restart left a temporary or the lock" >&2
    status=1
    continue
  fi
  echo "trial $trial: killed after ${delay_ms} ms ($left temporaries or locks left)," \
    "restarted from $(basename "${last:-the start (no checkpoint yet)}"):" \
    "mpm_final.h5 the reference's bit for bit"
done

for checkpoint in "$work"/reference/mpm_t*.h5; do
  name=$(basename "$checkpoint" .h5)
  [[ $name == mpm_t0.000 || $name == mpm_t1.200 ]] && continue
  out=from-$name
  if ! run "$out" --restart "$checkpoint" > /dev/null 2> "$work/$out.err"; then
    echo "FAIL: the restart from reference/$name.h5 failed:" >&2
    cat "$work/$out.err" >&2
    status=1
  elif ! "$python" "$src/tests/mpi/compare_by_id.py" "$work/reference/mpm_final.h5" \
    "$work/$out/mpm_final.h5" 0 > "$work/$out.compare" 2>&1; then
    echo "FAIL: the restart from reference/$name.h5 is not the reference bit for bit:" >&2
    cat "$work/$out.compare" >&2
    status=1
  else
    echo "restarted from reference/$name.h5: mpm_final.h5 the reference's bit for bit"
  fi
done
exit $status
