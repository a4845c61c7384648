#!/usr/bin/env bash
# A user's slope outside the source tree, the two ways docs/new-case.md gives:
#  1. with the installed programs: `cmake --install` to a temporary prefix, then, with only
#     PREFIX/bin (and the system's /usr/bin:/bin) on PATH, slide-new-case and `make` in a
#     folder outside the tree: the report is written, the checkpoints name the version
#     and commit that --version prints, and find_package(slide) finds the programs and
#     the pipeline;
#  2. with the source tree's pipeline and build: slide-new-case from tools/, make with BIN.
# The template's MPM end is cut to 6 s (its case file's own end_time, as a user would).
#
#   install_test.sh SOURCE_DIR BUILD_DIR WORK_DIR
set -euo pipefail
source=$1 build=$2 work=$3
fail() { echo "install_test: $*" >&2; exit 1; }
rm -rf "$work" && mkdir -p "$work/user" "$work/tree"
prefix=$work/prefix
cmake --install "$build" --prefix "$prefix" > "$work/install.log" ||
  { cat "$work/install.log"; fail "cmake --install failed"; }
for f in bin/fem-solve bin/fem2mpm bin/mpm-solve bin/slide-metrics bin/slide-new-case \
         share/slide/cases/pipeline.mk share/slide/cases/installed.mk \
         share/slide/cases/template/case.toml share/slide/tools/report.py \
         share/doc/slide/README.md share/doc/slide/docs/new-case.md share/doc/slide/LICENSE \
         lib/cmake/slide/slideConfig.cmake; do
  [[ -e $prefix/$f ]] || fail "not installed: $f"
done

short_case() {  # FOLDER: the template's case with the MPM phase cut to 6 s
  sed -i 's/^end_time = 20.0 .*/end_time = 6.0/' "$1/case.toml"
  grep -q '^end_time = 6.0$' "$1/case.toml" || fail "the template has no MPM end_time = 20.0 to cut"
}

# 1. Installed, only the prefix on PATH.
(
  export PATH=$prefix/bin:/usr/bin:/bin
  cd "$work/user"
  slide-new-case myslope > /dev/null
  short_case myslope
  make -C myslope > make.log 2>&1 || { tail -20 make.log; fail "make of the installed pipeline failed"; }
  grep -q "$prefix/bin/fem-solve" make.log || fail "the installed pipeline did not run the installed fem-solve"
  [[ -s myslope/out/report/report.md ]] || fail "no report from the installed pipeline"
  version=$(fem-solve --version)
  [[ $version =~ ^slide\ [0-9]+\.[0-9]+\.[0-9]+\ \(commit\ [0-9A-Za-z._-]+\)$ ]] ||
    fail "fem-solve --version: '$version'"
  producer=$(/usr/bin/python3 -c 'import h5py, sys; p = h5py.File(sys.argv[1], "r").attrs["producer"]; print(p.decode() if isinstance(p, bytes) else p)' \
             myslope/out/tt0/mpm_final.h5)
  [[ $producer == "mpm-solve ($version)" ]] || fail "producer '$producer', --version '$version'"
)

# find_package(slide) from a project that knows only the prefix.
mkdir -p "$work/package"
cat > "$work/package/CMakeLists.txt" <<'CMAKE'
cmake_minimum_required(VERSION 3.25)
project(uses_slide NONE)
find_package(slide 0.1 REQUIRED)
get_target_property(solver slide::fem-solve IMPORTED_LOCATION_RELEASE)
message(STATUS "slide ${slide_VERSION}: ${solver} ${slide_PIPELINE_MK}")
CMAKE
cmake -S "$work/package" -B "$work/package/build" -DCMAKE_PREFIX_PATH="$prefix" > "$work/package.log" ||
  { cat "$work/package.log"; fail "find_package(slide) failed"; }
grep -q "slide 0\.[0-9.]*: $prefix/bin/fem-solve $prefix/share/slide/cases/pipeline.mk" "$work/package.log" ||
  { cat "$work/package.log"; fail "find_package(slide) did not name the installed programs and pipeline"; }

# 2. The source tree's pipeline from a folder outside it.
cd "$work/tree"
"$source/tools/slide-new-case" myslope > /dev/null
short_case myslope
make -C myslope BIN="$build/bin" > make.log 2>&1 || { tail -20 make.log; fail "make with the source tree's pipeline failed"; }
[[ -s myslope/out/report/report.md ]] || fail "no report from the source tree's pipeline"
echo "install_test: ok"
