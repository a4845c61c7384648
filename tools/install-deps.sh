#!/usr/bin/env bash
# Installs, from Debian 12's own archive, every package the project needs to build,
# test and plot. Idempotent: when everything is present it only runs dpkg-query and
# returns in well under a second. Needs root (or sudo) only when something is missing.
#
#   tools/install-deps.sh         the serial build (the default)
#   tools/install-deps.sh --mpi   also OpenMPI and Debian's parallel HDF5, for the MPI
#                                 build (cmake -DSLIDE_MPI=ON, docs/parallel.md)
set -euo pipefail

mpi=0
case "${1:-}" in
  "") ;;
  --mpi) mpi=1 ;;
  *) echo "install-deps: unknown option '$1' (usage: tools/install-deps.sh [--mpi])" >&2; exit 2 ;;
esac

packages=(
  build-essential cmake ninja-build pkg-config git clang-format strace
  libeigen3-dev libhdf5-dev libvtk9-dev libcli11-dev libtomlplusplus-dev
  libnanoflann-dev libfmt-dev libgtest-dev libbenchmark-dev
  nlohmann-json3-dev  # OpenSees model import (print -JSON) and CB-Geo MPM input export
  python3 python3-h5py python3-matplotlib python3-numpy
  python3-pandas  # slide.to_dataframe (optional for users), which tools.python-module tests
  gmsh  # cases/slope-gmsh's mesh: the test gmsh.slope-gmsh remakes it from its .geo
)
# The MPI build's: mpirun and the MPI headers, HDF5 built on them (h5pcc). They coexist
# with the serial libhdf5-dev, which the serial build keeps using. procps: pkill, with
# which tests/mpi/kill_restart_test.sh kills a run (not on a minimal Debian image).
if ((mpi)); then packages+=(openmpi-bin libopenmpi-dev libhdf5-openmpi-dev procps); fi

missing=()
for p in "${packages[@]}"; do
  status=$(dpkg-query -W -f='${Status}' "$p" 2>/dev/null || true)
  [[ "$status" == "install ok installed" ]] || missing+=("$p")
done

if ((${#missing[@]} == 0)); then
  echo "install-deps: all ${#packages[@]} packages present"
  exit 0
fi

# ParaView's Python (python3-paraview, for pvpython and pvbatch) conflicts with VTK's
# (python3-vtk9), which libvtk9-dev depends on: with it installed, apt refuses libvtk9-dev
# with "pkgProblemResolver ... generated breaks". ParaView itself (the paraview package)
# coexists with the build.
is_installed() { [[ $(dpkg-query -W -f='${Status}' "$1" 2>/dev/null || true) == "install ok installed" ]]; }
if is_installed python3-paraview && [[ " ${missing[*]} " == *" libvtk9-dev "* ]]; then
  echo "install-deps: python3-paraview is installed and conflicts with libvtk9-dev (through" \
    "python3-vtk9): run 'apt-get remove python3-paraview' (the paraview package may stay)," \
    "then this again; use pvpython on another machine" >&2
  exit 1
fi

echo "install-deps: installing ${missing[*]}"
sudo_cmd=()
if [[ $(id -u) -ne 0 ]]; then sudo_cmd=(sudo); fi
export DEBIAN_FRONTEND=noninteractive
"${sudo_cmd[@]}" apt-get update -qq
"${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
echo "install-deps: done"
