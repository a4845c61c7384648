#!/usr/bin/env bash
# The command-line contract every program shares (docs/contract.md, common/base/program.hpp):
# --help prints usage on stdout and exits 0; a missing input, a broken case file and an
# unknown option each exit non-zero with exactly one line on stderr that names the
# culprit, and leave no output behind.
#
#   tests/common/programs_cli.sh BUILD_BIN_DIR SOURCE_DIR
set -uo pipefail
bin=$1
src=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
failures=0

fail() {
  echo "FAIL: $*"
  failures=$((failures + 1))
}

# run NAME EXPECTED_STATUS COMMAND...: runs the command with stdout and stderr captured.
run() {
  local name=$1 expected=$2
  shift 2
  "$@" >"$work/out" 2>"$work/err"
  status=$?
  # (the sanitize build: a report fails the check even where a non-zero exit is expected)
  if grep -qE 'ERROR: (Address|Leak)Sanitizer|: runtime error: ' "$work/err"; then
    fail "$name: sanitizer report: $(cat "$work/err")"
  fi
  if [[ $expected == nonzero ]]; then
    ((status != 0)) || fail "$name: exit status 0, expected non-zero"
  else
    ((status == expected)) || fail "$name: exit status $status, expected $expected"
  fi
}

# one_error_line NAME FRAGMENT: stderr is exactly one line and it contains FRAGMENT.
one_error_line() {
  local lines
  lines=$(wc -l <"$work/err")
  ((lines == 1)) || fail "$1: $lines stderr lines, expected 1: $(cat "$work/err")"
  grep -qF -- "$2" "$work/err" || fail "$1: stderr does not name '$2': $(cat "$work/err")"
}

# A case file with one impossible value, on a known line.
broken_case="$work/broken/case.toml"
mkdir -p "$work/broken"
sed 's/^poisson_ratio = 0.23/poisson_ratio = 0.5/' "$src/cases/column-short/case.toml" \
  >"$broken_case"
broken_line=$(grep -n '^poisson_ratio = 0.5' "$broken_case" | cut -d: -f1)
[[ -n $broken_line ]] || fail "could not break the column-short case file"

for program in fem-solve fem2mpm mpm-solve; do
  exe="$bin/$program"
  for flag in --help -h; do
    run "$program $flag" 0 "$exe" "$flag"
    grep -q "Usage:" "$work/out" || fail "$program $flag: no usage on stdout"
    [[ ! -s $work/err ]] || fail "$program $flag: wrote to stderr: $(cat "$work/err")"
  done
  # The GNU layout: the usage first, options as "-o, --output=DIR", the help and version
  # options last, the exit statuses; no line beyond 80 columns.
  head -1 "$work/out" | grep -qE "^Usage: $program \[OPTION\]\.\.\. [A-Z_]+$" ||
    fail "$program --help: first line '$(head -1 "$work/out")'"
  grep -qE '^  -o, --output=(DIR|FILE) ' "$work/out" || fail "$program --help: no '-o, --output=…' entry"
  grep -qE '^  -h, --help +display this help and exit$' "$work/out" || fail "$program --help: no -h entry"
  grep -qE '^      --version +output version information and exit$' "$work/out" ||
    fail "$program --help: no --version entry"
  grep -q '^Exit status:$' "$work/out" || fail "$program --help: no exit statuses"
  grep -qE '^ 2  a usage error' "$work/out" || fail "$program --help: no status 2"
  while IFS= read -r line; do  # characters, not bytes: the help has → and φ
    (( $(LC_ALL=C.UTF-8 bash -c 'echo ${#1}' _ "$line") <= 80 )) ||
      fail "$program --help: a line beyond 80 columns: $line"
  done < "$work/out"

  run "$program --version" 0 "$exe" --version
  grep -q "^slide " "$work/out" || fail "$program --version: no version on stdout"

  run "$program without arguments" nonzero "$exe"
  one_error_line "$program without arguments" "$program: error:"
done

for program in fem-solve mpm-solve; do
  exe="$bin/$program"
  out="$work/out-$program"
  run "$program missing case" nonzero "$exe" "$work/missing.toml" -o "$out"
  one_error_line "$program missing case" "missing.toml"
  [[ ! -e $out ]] || fail "$program missing case: created $out"

  run "$program broken case" nonzero "$exe" "$broken_case" -o "$out"
  one_error_line "$program broken case" "case.toml:$broken_line:"
  grep -qF "poisson_ratio" "$work/err" || fail "$program broken case: key not named"
  [[ ! -e $out ]] || fail "$program broken case: created $out"

  run "$program unknown option" 2 "$exe" "$src/cases/column-short/case.toml" -o "$out" \
    --no-such-option
  one_error_line "$program unknown option" "--no-such-option"
  [[ ! -e $out ]] || fail "$program unknown option: created $out"
done

for until in nan -2; do
  for program in fem-solve mpm-solve; do
    out="$work/out-until-$program"
    run "$program --until $until" nonzero "$bin/$program" "$src/cases/column-short/case.toml" \
      -o "$out" --until "$until" --no-vtk
    one_error_line "$program --until $until" "--until"
    [[ ! -e $out ]] || fail "$program --until $until: created $out"
  done
done

run "mpm-solve --threads 0" 2 "$bin/mpm-solve" "$src/cases/column-short/case.toml" -o "$work/t0" \
  --threads 0
one_error_line "mpm-solve --threads 0" "must be > 0"

run "fem2mpm missing checkpoint" nonzero "$bin/fem2mpm" "$work/missing.h5" -o "$work/p.h5"
one_error_line "fem2mpm missing checkpoint" "missing.h5"
[[ ! -e $work/p.h5 ]] || fail "fem2mpm missing checkpoint: created the particle file"

printf 'not an HDF5 file\n' >"$work/garbage.h5"
run "fem2mpm garbage checkpoint" nonzero "$bin/fem2mpm" "$work/garbage.h5" -o "$work/p.h5"
one_error_line "fem2mpm garbage checkpoint" "garbage.h5"
[[ ! -e $work/p.h5 ]] || fail "fem2mpm garbage checkpoint: created the particle file"

run "mpm-solve garbage particles" nonzero "$bin/mpm-solve" \
  "$src/cases/column-short/case.toml" -o "$work/out-mpm" --particles "$work/garbage.h5"
one_error_line "mpm-solve garbage particles" "garbage.h5"

# slide-element (PM4Sand's element tests): usage, a refused command line, a broken case, a
# material the case does not have, an inadmissible D_R; none leaves a file behind.
element="$bin/slide-element"
run "slide-element --help" 0 "$element" --help
grep -q "Usage:" "$work/out" || fail "slide-element --help: no usage on stdout"
run "slide-element without a subcommand" 2 "$element"
one_error_line "slide-element without a subcommand" "slide-element: error:"
run "slide-element unknown option" 2 "$element" cyclic "$work/c.csv" --relative-density 0.5 \
  --contraction-rate 0.5 --no-such-option
one_error_line "slide-element unknown option" "--no-such-option"
run "slide-element broken case" nonzero "$element" cyclic "$work/c.csv" --case "$broken_case" \
  --material soil
one_error_line "slide-element broken case" "case.toml:$broken_line:"
run "slide-element unknown material" nonzero "$element" cyclic "$work/c.csv" \
  --case "$src/cases/liquefiable-deposit/case.toml" --material clay
one_error_line "slide-element unknown material" "no material called \"clay\""
run "slide-element absurd D_R" nonzero "$element" calibrate "$work/cal" --relative-density 7
one_error_line "slide-element absurd D_R" "relative_density = 7"
run "slide-element no h_po" nonzero "$element" cyclic "$work/c.csv" --relative-density 0.5
one_error_line "slide-element no h_po" "--contraction-rate"
[[ ! -e $work/c.csv && ! -e $work/cal ]] || fail "slide-element: a refused run left a file"

if ((failures > 0)); then
  echo "$failures failure(s)"
  exit 1
fi
echo "programs_cli: all checks passed"
