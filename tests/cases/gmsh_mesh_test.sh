#!/usr/bin/env bash
# cases/slope-gmsh: remakes slope.msh from slope.geo with the installed Gmsh, the way the
# case's `make mesh` does, and compares it with the committed file.
#
#   gmsh_mesh_test.sh GMSH PYTHON SOURCE_DIR WORK_DIR
#
# Both meshes must pass check_slope_gmsh_mesh.py (all quadrangles, the areas of the two
# materials and the boundary groups of slope.geo). With the Gmsh that wrote the committed
# file (WRITTEN_BY below; Gmsh's meshing is deterministic for a given version: two runs
# give the same bytes) the two files must be identical, so a change to slope.geo without
# its slope.msh, or the other way round, fails here. Another Gmsh version meshes
# differently: then only the checks apply, and the test says so.
set -euo pipefail
gmsh=$1 python=$2 source=$3 work=$4
WRITTEN_BY=4.8.4
case_dir=$source/cases/slope-gmsh
here=$(cd "$(dirname "$0")" && pwd)

rm -rf "$work" && mkdir -p "$work"
"$gmsh" "$case_dir/slope.geo" -2 -format msh41 -o "$work/slope.msh" > "$work/gmsh.log" 2>&1 ||
  { cat "$work/gmsh.log" >&2; echo "gmsh failed on slope.geo" >&2; exit 1; }

echo "committed slope.msh:"
"$python" "$here/check_slope_gmsh_mesh.py" "$case_dir/slope.msh"
echo "remade from slope.geo:"
"$python" "$here/check_slope_gmsh_mesh.py" "$work/slope.msh"

version=$("$gmsh" --version 2>&1 | tail -n 1)
if [[ $version != "$WRITTEN_BY" ]]; then
  echo "Gmsh $version, not $WRITTEN_BY that wrote slope.msh: its mesh differs; compared the checks only"
  exit 0
fi
if ! cmp -s "$case_dir/slope.msh" "$work/slope.msh"; then
  echo "cases/slope-gmsh/slope.msh is not what Gmsh $version makes of slope.geo:" \
    "run 'make -C cases/slope-gmsh mesh' and commit both" >&2
  diff "$case_dir/slope.msh" "$work/slope.msh" | head -n 10 >&2 || true  # diff: SIGPIPE
  exit 1
fi
echo "slope.msh is the mesh Gmsh $version makes of slope.geo, byte for byte"
