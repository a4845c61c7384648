#!/bin/sh
# docs/method.md §8, verification 3: the sliding block in fem-solve, and in mpm-solve after
# a transfer before the shaking (t_T = 0) and during it (t_T = 0.8 s, the main lobe of the
# pulse), each against the Newmark sliding-block integral within 5 %
# (tools/seismic.py sliding-block exits 1 otherwise).
#   sliding_block_test.sh BIN SOURCE_DIR WORK_DIR PYTHON
set -eu
bin=$1 src=$2 work=$3 python=$4
case=$src/tests/seismic/sliding-block/case.toml
rm -rf "$work"
"$bin/fem-solve" "$case" -o "$work/fem" --no-vtk
for tt in 0.000 0.800; do
  "$bin/fem2mpm" "$work/fem/fem_t$tt.h5" -o "$work/tt$tt/particles.h5"
  "$bin/mpm-solve" "$case" --particles "$work/tt$tt/particles.h5" -o "$work/tt$tt" --no-vtk
  "$python" "$src/tools/seismic.py" sliding-block "$case" "$work/fem" "$work/tt$tt" "$work/report$tt"
done

# The same on a plane inclined by 10° (incline.toml, gravity turned by θ), both phases
# checked, the transfer before the shaking and during it (t_T = 1 s).
incline=$src/tests/seismic/sliding-block/incline.toml
"$bin/fem-solve" "$incline" -o "$work/incline/fem" --no-vtk
for tt in 0.000 1.000; do
  "$bin/fem2mpm" "$work/incline/fem/fem_t$tt.h5" -o "$work/incline/tt$tt/particles.h5"
  "$bin/mpm-solve" "$incline" --particles "$work/incline/tt$tt/particles.h5" -o "$work/incline/tt$tt" \
    --no-vtk
  "$python" "$src/tools/seismic.py" sliding-block "$incline" "$work/incline/fem" "$work/incline/tt$tt" \
    "$work/incline/report$tt"
done
