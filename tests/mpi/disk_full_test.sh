#!/usr/bin/env bash
# A full disk under MPI ends every rank cleanly (tests/mpi/README.md): mpm-solve writes
# column-short into a small tmpfs that another process fills once the run has started;
# every case must end with status 1, one line of ours, no temporary file, no lock, and
# the checkpoints written before it whole. Cases: 2 ranks meeting the full disk at a
# checkpoint, 2 ranks at a VTK frame, 1 rank under mpirun (it used to segfault in
# MPI_Finalize, status 139), and a disk too small for the run from the start (refused
# before the folder is made). Needs root to mount the tmpfs: skipped otherwise.
#   disk_full_test.sh BIN_DIR SOURCE_DIR WORK_DIR PYTHON MPIEXEC
set -uo pipefail
bin=$1 src=$2 work=$3 python=$4 mpiexec=$5
case_file=$src/cases/column-short/case.toml
mkdir -p "$work"
disk=$work/disk
mkdir -p "$disk"
if [[ $(id -u) -ne 0 ]] || ! mount -t tmpfs -o size=300M tmpfs "$disk" 2> /dev/null; then
  echo "SKIPPED: mounting a small tmpfs needs root"
  exit 0
fi
trap 'umount "$disk" 2> /dev/null' EXIT
status=0
fail() { echo "FAIL ($1): $2" >&2; status=1; }

# run NAME RANKS LEAVE_MB [mpm-solve options]: the run into $disk/NAME; once it has written
# its first checkpoint, a filler leaves LEAVE_MB of the disk free.
run() {
  local name=$1 ranks=$2 leave=$3
  shift 3
  rm -rf "${disk:?}"/*
  local log=$work/$name.log
  timeout 120 "$mpiexec" -q -n "$ranks" "$bin/mpm-solve" "$case_file" -o "$disk/$name" \
    --threads 1 -q "$@" > "$log" 2> "$work/$name.err" &
  local pid=$!
  for _ in $(seq 600); do
    [[ -e $disk/$name/mpm_t0.000.h5 ]] && break
    sleep 0.05
  done
  local avail
  avail=$(df -m --output=avail "$disk" | tail -1)
  dd if=/dev/zero of="$disk/filler" bs=1M count=$((avail - leave)) 2> /dev/null
  wait $pid
  local code=$?
  local ours
  ours=$(grep -c '^mpm-solve: error:' "$work/$name.err")
  if [[ $code -ne 1 || $ours -ne 1 ]]; then
    fail "$name" "status $code (1 expected), $ours lines of ours:"
    cat "$work/$name.err" >&2
    return
  fi
  local left
  left=$(find "$disk" -name '*.tmp-*' -o -name '.slide-lock' | wc -l)
  [[ $left -eq 0 ]] && left_text="none" || { left_text=$(find "$disk" -name '*.tmp-*' -o -name '.slide-lock'); fail "$name" "left behind: $left_text"; }
  for h5 in "$disk/$name"/*.h5; do
    [[ -e $h5 ]] || continue
    "$python" -c 'import sys, h5py; f = h5py.File(sys.argv[1], "r"); f["particles/mass"][:]' \
      "$h5" 2> /dev/null || fail "$name" "$h5 is not whole"
  done
  echo "$name: status 1, one line ($(grep '^mpm-solve: error:' "$work/$name.err" | cut -c1-160)), no temporary or lock left"
}

run checkpoint-2-ranks 2 12 --no-vtk --until 4
run frame-2-ranks 2 10 --vtk-every 0.5 --until 4
run checkpoint-1-rank 1 12 --no-vtk --until 4

# A disk too small for the whole run: refused before anything is written.
rm -rf "${disk:?}"/*
dd if=/dev/zero of="$disk/filler" bs=1M count=$(($(df -m --output=avail "$disk" | tail -1) - 20)) 2> /dev/null
timeout 60 "$mpiexec" -q -n 2 "$bin/mpm-solve" "$case_file" -o "$disk/small" --threads 1 -q \
  --until 4 2> "$work/small.err"
code=$?
if [[ $code -ne 1 ]] || ! grep -q "whose disk has .* GB free" "$work/small.err" || [[ -e $disk/small ]]; then
  fail small "status $code, folder $([[ -e $disk/small ]] && echo made || echo absent):"
  cat "$work/small.err" >&2
else
  echo "small: refused before writing: $(cut -c1-120 "$work/small.err")"
fi
exit $status
