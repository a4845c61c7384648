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

# Why the elastic block slides farther than the rigid one (mpm/README.md, "Base motion"):
# every stop sets it vibrating, and only damping takes the vibration out. Undamped, FE
# slides more than 10 % beyond the integral (measured +40 %); MPM with a 5 % PIC share
# dissipates more in the transfer than APIC at the same Courant number and keeps less
# than half of APIC's excess (measured +1.34 % against +3.22 %).
errors() {  # the two signed errors in % of a "sliding block:" line of seismic.py
  "$python" "$src/tools/seismic.py" sliding-block "$@" |
    sed -n 's/^sliding block:.*(\([+-][0-9.]*\) %).*(\([+-][0-9.]*\) %).*/\1 \2/p'
}
mechanism=$work/incline-mechanism
mkdir -p "$mechanism"
sed -e 's/^rayleigh_stiffness = .*/rayleigh_stiffness = 0.0/' \
    -e 's/^velocity_transfer = .*/velocity_transfer = "flip-pic"\npic_fraction = 0.05/' \
    "$incline" > "$mechanism/case.toml"
"$bin/fem-solve" "$mechanism/case.toml" -o "$mechanism/fem" --no-vtk --until 3
"$bin/mpm-solve" "$mechanism/case.toml" --particles "$work/incline/tt0.000/particles.h5" \
  -o "$mechanism/mpm" --no-vtk --other-case
apic=$(errors "$incline" "$work/incline/fem" "$work/incline/tt0.000" "$mechanism/report-apic")
undamped=$(errors "$mechanism/case.toml" "$mechanism/fem" "$mechanism/mpm" "$mechanism/report" || true)
echo "APIC (FE, MPM): $apic; undamped FE, MPM with a 5 % PIC share: $undamped"
echo "$apic $undamped" | awk 'NF != 4 { print "sliding block mechanism: cannot read the errors"; exit 1 }
  $3 <= 10 { printf "undamped FE only %+.2f %% beyond the integral (expected > +10 %%)\n", $3; exit 1 }
  $4 >= $2 / 2 { printf "MPM with a 5 %% PIC share %+.2f %%, APIC %+.2f %% (expected under half)\n", $4, $2; exit 1 }'
