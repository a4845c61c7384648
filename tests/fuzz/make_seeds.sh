#!/usr/bin/env bash
# Writes the seed corpora of the five fuzz drivers (tests/fuzz/README.md), one folder per
# reader with two parts:
#   OUT/<reader>/valid/   files the reader must accept (the seeded tests check it)
#   OUT/<reader>/more/    broken or foreign files, seeds for mutation only
# case_file: the repository's cases, the fuzzing fixtures and tests/fuzz/corpus/case_file;
# gmsh: the .msh files of tests/common/data and tests/fuzz/corpus/gmsh; the checkpoint
# readers: files written by running the programs (BIN_DIR) on
# tests/fuzz/cases/fuzz-checkpoints for a few steps (--until), kept out of the repository
# (tens of kB each, HDF5 metadata mostly):
#   fem_checkpoint   geostatic and failure stage of quad4-1gp, failure stage of tri3 and
#                    of quad4-2x2 with updated Lagrangian kinematics
#   particle_file    fem2mpm's particle files of the quad4-1gp and the tri3 model
#   mpm_checkpoint   mpm-solve checkpoints of a transferred and of a pure MPM run
# and in each more/ one file of each other kind.
#
#   tests/fuzz/make_seeds.sh BIN_DIR OUT_DIR
set -euo pipefail
bin=$1
out=$2
here="$(cd "$(dirname "$0")" && pwd)"
root="$(cd "$here/../.." && pwd)"
fixture="$here/cases/fuzz-checkpoints/case.toml"
work="$out/work"
export OMP_NUM_THREADS=1

rm -rf "$out"
readers=(case_file gmsh fem_checkpoint particle_file mpm_checkpoint opensees_model opensees_recorder)
for reader in "${readers[@]}"; do
  mkdir -p "$out/$reader/valid" "$out/$reader/more"
done
mkdir -p "$work"

# ---- text readers: files of the repository
# A Gmsh case names a .msh file that is not beside its seed, so the reader refuses it
# (cases/slope-gmsh, tests/fuzz/cases/fuzz-gmsh): seeds for mutation only.
for file in "$root"/cases/*/case.toml; do
  name=$(basename "$(dirname "$file")")
  part=valid
  grep -qE '^generator *= *"gmsh"' "$file" && part=more
  cp "$file" "$out/case_file/$part/$name.toml"
done
cp "$fixture" "$out/case_file/valid/fuzz-checkpoints.toml"
cp "$here"/corpus/case_file/*.toml "$out/case_file/valid/"
cp "$here/cases/fuzz-gmsh/case.toml" "$out/case_file/more/fuzz-gmsh.toml"
for file in "$root"/tests/common/data/*.msh; do
  case $(basename "$file") in
    two_quads_v22.msh | two_quads_v41.msh) cp "$file" "$out/gmsh/valid/" ;;
    *) cp "$file" "$out/gmsh/more/" ;;
  esac
done
cp "$here"/corpus/gmsh/*.msh "$out/gmsh/valid/"
# OpenSees: the elastic column's model and recorders (tests/tools/interop/data/column).
column="$root/tests/tools/interop/data/column"
cp "$column/model.json" "$out/opensees_model/valid/"
cp "$column/disp.out" "$column/stress.out" "$out/opensees_recorder/valid/"
cp "$column/vel.out" "$column/strain.out" "$out/opensees_recorder/more/"
cp "$column/disp.out" "$out/opensees_model/more/"
cp "$column/model.json" "$out/opensees_recorder/more/"

# ---- checkpoint readers: files the programs write
run() { "$@" --quiet > "$work/last.log" 2>&1 || { echo "make_seeds: failed: $*" >&2; cat "$work/last.log" >&2; exit 1; }; }
run "$bin/fem-solve" "$fixture" -o "$work/fem" --until 0.02 --no-vtk
run "$bin/fem-solve" "$fixture" -o "$work/fem-tri3" --until 0.01 --element tri3 --no-vtk
run "$bin/fem-solve" "$fixture" -o "$work/fem-2x2" --until 0.01 --element quad4-2x2 \
  --kinematics updated-lagrangian --no-vtk
run "$bin/fem2mpm" "$work/fem/fem_t0.020.h5" -o "$work/particles.h5" --case "$fixture"
run "$bin/fem2mpm" "$work/fem-tri3/fem_t0.010.h5" -o "$work/particles-tri3.h5" \
  --case "$fixture" --particles-per-element 3 --stress-interpolation rbf-local
run "$bin/mpm-solve" "$fixture" -o "$work/mpm" --particles "$work/particles.h5" --until 0.03 --no-vtk
run "$bin/mpm-solve" "$fixture" -o "$work/pure" --until 0.01 --shape-function linear --no-vtk

cp "$work/fem/fem_t0.000.h5" "$out/fem_checkpoint/valid/quad4-1gp-geostatic.h5"
cp "$work/fem/fem_t0.020.h5" "$out/fem_checkpoint/valid/quad4-1gp-failure.h5"
cp "$work/fem-tri3/fem_t0.010.h5" "$out/fem_checkpoint/valid/tri3-failure.h5"
cp "$work/fem-2x2/fem_t0.010.h5" "$out/fem_checkpoint/valid/quad4-2x2-updated-lagrangian.h5"
cp "$work/particles.h5" "$out/particle_file/valid/quad4-1gp-rbf.h5"
cp "$work/particles-tri3.h5" "$out/particle_file/valid/tri3-rbf-local.h5"
cp "$work/mpm/mpm_t0.030.h5" "$out/mpm_checkpoint/valid/transferred.h5"
cp "$work/pure/mpm_t0.010.h5" "$out/mpm_checkpoint/valid/pure-mpm-linear.h5"
cp "$work/particles.h5" "$work/mpm/mpm_t0.030.h5" "$out/fem_checkpoint/more/"
cp "$work/fem/fem_t0.020.h5" "$work/mpm/mpm_t0.030.h5" "$out/particle_file/more/"
cp "$work/fem/fem_t0.020.h5" "$work/particles.h5" "$out/mpm_checkpoint/more/"
rm -rf "$work"

for reader in "${readers[@]}"; do
  echo "make_seeds: $reader: $(ls "$out/$reader/valid" | wc -l) valid + $(ls "$out/$reader/more" | wc -l) more files, $(du -sk "$out/$reader" | cut -f1) kB"
done
