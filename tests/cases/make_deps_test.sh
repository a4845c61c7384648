#!/usr/bin/env bash
# The pipeline's runs depend on every file the case names: after the base motion's record
# is edited, `make fem` is stale (it used to be left up to date). A scratch copy of the
# pipeline with slope-seismic shaken by a record file; the FE phase's last checkpoint is
# stood in for by an empty file (make only compares dates here).
#
#   make_deps_test.sh SOURCE_DIR BIN SCRATCH
set -uo pipefail
src=$1
bin=$2
scratch=$3
rm -rf "$scratch"
tree=$scratch/tree
mkdir -p "$tree/cases/slope-seismic" "$tree/tools"
cp "$src"/cases/{pipeline.mk,paths.mk,out.mk} "$tree/cases/"
cp "$src"/cases/slope-seismic/Makefile "$tree/cases/slope-seismic/"
cp "$src"/tools/clean-outputs.sh "$tree/tools/"
printf '0 0\n1 0.5\n2 -0.5\n3 0\n' > "$tree/cases/slope-seismic/record.txt"
# The sine motion replaced by the record file.
sed -e '/^\[fem.motion.horizontal\]/,/^$/d' "$src/cases/slope-seismic/case.toml" > "$tree/cases/slope-seismic/case.toml"
cat >> "$tree/cases/slope-seismic/case.toml" <<'TOML'

[fem.motion.horizontal]
source = "file"
file = "record.txt"
units = "m/s2"
TOML
out=$scratch/out
make_q() { make -q -C "$tree/cases/slope-seismic" fem OUT="$out" BIN="$bin" 2> "$scratch/err"; }
make -s -C "$tree/cases/slope-seismic" "$out/case.mk" OUT="$out" BIN="$bin" > /dev/null 2> "$scratch/err" ||
  { echo "FAIL: case-info: $(cat "$scratch/err")"; exit 1; }
grep -q "^CASE_FILES=.*record.txt" "$out/case.mk" || { echo "FAIL: case.mk: $(cat "$out/case.mk")"; exit 1; }
fem_end=$(sed -n 's/^FEM_END=//p' "$out/case.mk")
mkdir -p "$out/fem" && touch "$out/fem/fem_t$(printf '%.3f' "$fem_end").h5"
make_q && echo "up to date" || { echo "FAIL: not up to date before the edit"; exit 1; }
sleep 1.1 && touch "$tree/cases/slope-seismic/record.txt"
if make_q; then echo "FAIL: make fem is up to date after the motion record was edited"; exit 1; fi
echo "make_deps_test: editing the motion record makes the FE phase stale"
