#!/usr/bin/env bash
# `make clean` removes what the pipeline made and nothing else (issue: from a checkout's
# root, `make -C cases/geostatic-4x4 clean OUT=` removed the whole checkout). In a scratch
# copy of the pipeline's Makefiles laid out as the repository (cases/, tools/), every
# hostile OUT (empty, the root, the home folder, the tree's root, a folder above it, an
# unmarked folder, one exported in the environment) leaves every file in place, and a
# marked OUT loses only the pipeline's files.
#
#   clean_test.sh SOURCE_DIR SCRATCH
set -uo pipefail
src=$1
scratch=$2
rm -rf "$scratch"
tree=$scratch/tree
mkdir -p "$tree/cases" "$tree/tools" "$scratch/home" "$scratch/above"
cp "$src"/cases/{Makefile,pipeline.mk,paths.mk,out.mk} "$tree/cases/"
for c in "$src"/cases/*/; do
  name=$(basename "$c")
  [[ -f $c/Makefile ]] || continue
  mkdir -p "$tree/cases/$name" && cp "$c"/Makefile "$c"/*.toml "$tree/cases/$name/"
done
cp "$src"/tools/clean-outputs.sh "$tree/tools/"
# Files that must survive: in the tree, at its root, in the home folder, in an unmarked
# folder whose names look like the pipeline's.
for f in "$tree/keep.txt" "$tree/cases/keep.txt" "$scratch/home/report" "$scratch/home/fem" \
  "$scratch/above/keep.txt" "$scratch/unmarked/fem/keep.h5" "$scratch/unmarked/report"; do
  mkdir -p "$(dirname "$f")" && echo keep > "$f"
done
mkdir -p "$tree/.git" && echo keep > "$tree/.git/HEAD"
log=$(mktemp)
trap 'rm -f "$log"' EXIT
count() { find "$scratch" -type f -exec md5sum {} + | sort | md5sum; }
before=$(count)
failures=0
try() {  # try DESCRIPTION EXPECTED_STATUS make-arguments... (run from the tree's root)
  local what=$1 expected=$2
  shift 2
  (cd "$tree" && env HOME="$scratch/home" "$@" > "$log" 2>&1)
  local status=$? ok=0
  if [[ $expected == nonzero ]]; then ((status != 0)) && ok=1; else ((status == expected)) && ok=1; fi
  if ((ok == 0)); then
    echo "FAIL $what: status $status"; cat "$log"; failures=$((failures + 1))
  fi
  if [[ $(count) != "$before" ]]; then
    echo "FAIL $what: files changed"; cat "$log"; failures=$((failures + 1))
  fi
}
case_make=(make -s -C cases/geostatic-4x4 clean)
try "OUT= (empty)" nonzero "${case_make[@]}" OUT=
try "OUT=/" nonzero "${case_make[@]}" OUT=/
try "OUT=~" nonzero "${case_make[@]}" OUT="$scratch/home"
try "OUT=the tree's root" nonzero "${case_make[@]}" OUT="$tree"
try "OUT=above the tree" nonzero "${case_make[@]}" OUT="$scratch"
try "OUT=. from the tree's root" nonzero "${case_make[@]}" OUT=.
try "OUT=an unmarked folder" nonzero "${case_make[@]}" OUT="$scratch/unmarked"
try "OUT in the environment" 0 env OUT="$tree" "${case_make[@]}"
try "make -C cases clean OUT=" nonzero make -s -C cases clean OUT=
try "make -C cases clean with OUT in the environment" 0 env OUT="$tree" make -s -C cases clean
grep -q "of the environment is ignored" "$log" ||
  { echo "FAIL: no note that the environment's OUT is ignored"; failures=$((failures + 1)); }

# A marked OUT: the pipeline's files go, a file of the user's and OUT stay.
out=$scratch/runs
mkdir -p "$out/fem" "$out/tt2" "$out/report"
touch "$out/.slide-outputs" "$out/case.mk" "$out/sweep.csv" "$out/fem/fem_t0.000.h5" \
  "$out/tt2/particles.h5" "$out/notes.txt"
(cd "$tree" && HOME="$scratch/home" make -s -C cases/geostatic-4x4 clean OUT="$out") ||
  { echo "FAIL: clean of a marked OUT"; failures=$((failures + 1)); }
left=$(cd "$out" && find . -mindepth 1 | sort | tr '\n' ' ')
[[ $left == "./notes.txt " ]] || { echo "FAIL: left in OUT: $left"; failures=$((failures + 1)); }
rm "$out/notes.txt" && touch "$out/.slide-outputs" "$out/case.mk"
(cd "$tree" && make -s -C cases/geostatic-4x4 clean OUT="$out")
[[ ! -e $out ]] || { echo "FAIL: an OUT left empty stays"; failures=$((failures + 1)); }

if ((failures > 0)); then echo "$failures failure(s)"; exit 1; fi
echo "clean_test: every hostile OUT refused or ignored, every file kept"
