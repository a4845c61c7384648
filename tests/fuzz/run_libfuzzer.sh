#!/usr/bin/env bash
# Runs the seven libFuzzer drivers of a SLIDE_FUZZ=ON build (the target `fuzz`; tools/fuzz.sh
# sets it all up), each for SECONDS with its seeds and dictionary, in libFuzzer's fork
# mode so that a crash, a leak, an out-of-memory or a hang is saved and counted and the
# run goes on. Per reader in FUZZ_DIR:
#   corpus-<reader>/     the corpus libFuzzer grows from the seeds
#   crashes-<reader>/    the inputs of findings (crash-*, leak-*, oom-*, timeout-*), each
#                        with <input>.txt: its symbolised report, from a rerun of the input
#   log-<reader>.txt     libFuzzer's log
# and prints per reader: executions, executions/s, findings, corpus size. Every run starts
# from the seeds alone (the seeds follow the writers' current format; an old corpus would
# keep finding the faults of an old format): the folders of the run before are moved to
# FUZZ_DIR/previous/.
#
#   tests/fuzz/run_libfuzzer.sh BIN_DIR FUZZ_DIR SECONDS
#
# SLIDE_FUZZ_READERS (space-separated, default all seven) runs only those readers; the
# folders of the others are left as they are, and the summary covers the readers run.
set -euo pipefail
bin=$1
fuzz_dir=$2
seconds=$3
here="$(cd "$(dirname "$0")" && pwd)"
all_readers=(case_file gmsh fem_checkpoint particle_file mpm_checkpoint opensees_model opensees_recorder)
read -r -a readers <<< "${SLIDE_FUZZ_READERS:-${all_readers[*]}}"
for reader in "${readers[@]}"; do
  [[ " ${all_readers[*]} " == *" $reader "* ]] ||
    { echo "fuzz: unknown reader '$reader' (the readers: ${all_readers[*]})" >&2; exit 2; }
done

export OMP_NUM_THREADS=1
# allocator_may_return_null: an absurd allocation (a corrupted size, 2^50 bytes) returns
# NULL as glibc's malloc does, instead of stopping ASan; allocations above -rss_limit_mb
# are still findings (libFuzzer's malloc limit).
export ASAN_OPTIONS=${ASAN_OPTIONS:-abort_on_error=1:detect_leaks=1:symbolize=1:allocator_may_return_null=1}
export LSAN_OPTIONS=${LSAN_OPTIONS:-suppressions=$here/lsan.supp:print_suppressions=0}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
symbolizer=$(command -v llvm-symbolizer || command -v llvm-symbolizer-14 || true)
[[ -n $symbolizer ]] && export ASAN_SYMBOLIZER_PATH=$symbolizer
# The drivers' per-process scratch folders (fuzz_support.hpp), removed at the end.
export SLIDE_FUZZ_SCRATCH
SLIDE_FUZZ_SCRATCH=$(mktemp -d "${TMPDIR_FUZZ:-/dev/shm}/slide-fuzz-run.XXXXXX")
trap 'rm -rf "$SLIDE_FUZZ_SCRATCH"' EXIT

"$here/make_seeds.sh" "$bin" "$fuzz_dir/seeds"

dictionary() {
  case $1 in
    case_file) echo "$here/dict/case_file.dict" ;;
    gmsh) echo "$here/dict/gmsh.dict" ;;
    *) echo "$here/dict/checkpoint.dict" ;;
  esac
}

summary=()
for reader in "${readers[@]}"; do
  corpus="$fuzz_dir/corpus-$reader"
  crashes="$fuzz_dir/crashes-$reader"
  log="$fuzz_dir/log-$reader.txt"
  if [[ -e $corpus || -e $crashes || -e $log ]]; then
    mkdir -p "$fuzz_dir/previous"
    rm -rf "$fuzz_dir/previous/"*"-$reader" "$fuzz_dir/previous/log-$reader.txt"
    for old in "$corpus" "$crashes" "$log"; do [[ -e $old ]] && mv "$old" "$fuzz_dir/previous/"; done
  fi
  mkdir -p "$corpus" "$crashes"
  echo "fuzz: $reader for $seconds s (log: $log)"
  started=$(date +%s)
  # -timeout: an input taking more than 10 s is a hang; -rss_limit_mb: more than 2 GB
  # is an out-of-memory finding (the seeds need a few tens of MB). -detect_leaks=0: no
  # leak scan after every input whose mallocs and frees differ (libhdf5 leaks on most
  # corrupted files, lsan.supp, and the scans cut the rate by 8); leaks are still
  # checked when each fork job exits.
  "$bin/fuzz_$reader" -fork=1 -ignore_crashes=1 -ignore_ooms=1 -ignore_timeouts=1 -detect_leaks=0 \
    -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -close_fd_mask=3 \
    -dict="$(dictionary "$reader")" -artifact_prefix="$crashes/" -print_final_stats=1 -print_funcs=0 \
    "$corpus" "$fuzz_dir/seeds/$reader" > "$log" 2>&1 || true
  elapsed=$(($(date +%s) - started))
  # Fork mode's status lines: "#EXECS: cov: … corp: N exec/s: R oom/timeout/crash: A/B/C …".
  last=$(grep -E '^#[0-9]+: cov:' "$log" | tail -1 || true)
  execs=$(sed -nE 's/^#([0-9]+):.*/\1/p' <<< "$last")
  rate=$(( ${execs:-0} / (elapsed > 0 ? elapsed : 1) ))
  findings=$(find "$crashes" -maxdepth 1 -type f ! -name '*.txt' | wc -l)
  corpus_size=$(find "$corpus" -type f | wc -l)
  summary+=("$(printf '%-15s %12s %10s %9s %12s' "$reader" "${execs:-?}" "$rate" "$findings" "$corpus_size")")
  # A symbolised report of each finding, from a rerun of its input, with whole stacks
  # (the slow unwinder goes through Debian's libhdf5, which has no frame pointers).
  for input in "$crashes"/*; do
    [[ -f $input && $input != *.txt && ! -f $input.txt ]] || continue
    (ASAN_OPTIONS="$ASAN_OPTIONS:fast_unwind_on_malloc=0:fast_unwind_on_fatal=0:malloc_context_size=40" \
      "$bin/fuzz_$reader" -timeout=10 -rss_limit_mb=2048 "$input" > "$input.txt" 2>&1 || true
    ) 2> /dev/null  # the subshell, not this shell, reports the abort (to /dev/null)
  done
done

# One line per finding: its kind and the innermost named frames, in libhdf5 and in ours.
classify() {
  local report=$1 kind frames
  kind=$(grep -m1 -oE 'ERROR: [A-Za-z]+: [A-Za-z-]+( [a-z-]+)*|runtime error: [^:]*|fuzz finding: [^:]*|ALARM|timeout after' "$report" || true)
  frames=$(grep -E '^ +#[0-9]+ ' "$report" |
    sed -nE 's/^ +#[0-9]+ 0x[0-9a-f]+ in ([A-Za-z_][A-Za-z0-9_:]*).*/\1/p' |
    grep -vE '^(malloc|calloc|realloc|free|strdup|__interceptor|__asan|__sanitizer|__ubsan|fuzzer|__libc|_start|main|raise|abort|std::)' |
    grep -vE '^(H5C_|H5C__|H5AC_|H5FL_|H5MM_|H5F_sizeof)' | grep -E '^(H5|slide::)' | awk '!/^slide::/ && !h {h=$0} /^slide::/ && !o {o=$0} END {print h " | " o}')
  echo "${kind:-(did not reproduce alone)} | $frames"
}

echo
echo "fuzz: $seconds s per reader"
printf '%-15s %12s %10s %9s %12s\n' reader executions 'execs/s' findings 'corpus size'
printf '%s\n' "${summary[@]}"
echo
echo "findings by class (count, kind | innermost HDF5 frame | innermost frame of ours):"
for reader in "${readers[@]}"; do
  for report in "$fuzz_dir/crashes-$reader"/*.txt; do
    if [[ -f $report ]]; then echo "$reader: $(classify "$report")"; fi
  done
done | sort | uniq -c | sort -rn
echo "findings and their reports: $fuzz_dir/crashes-<reader>/ (an input and its .txt)"
# The status says whether anything was found: 0 only for a run without findings.
total=0
for reader in "${readers[@]}"; do
  total=$((total + $(find "$fuzz_dir/crashes-$reader" -maxdepth 1 -type f ! -name '*.txt' | wc -l)))
done
echo "fuzz: $total finding(s) in all"
((total == 0))
