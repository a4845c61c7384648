#!/usr/bin/env bash
# One case's chain with cut end times, fem-solve -> fem2mpm -> mpm-solve -> slide-metrics,
# and its key numbers against the stored references (tests/cases/references.txt).
#
#   case_chain.sh BIN_DIR SOURCE_DIR WORK_DIR CASE FEM_UNTIL TT MPM_UNTIL [--record]
#
# FEM_UNTIL = 0 runs the geostatic stage only. --record prints the measured numbers in
# the references format instead of comparing (for a deliberate change of the physics:
# paste them into references.txt and say why in the commit).
set -euo pipefail
bin=$1 source=$2 work=$3 name=$4 fem_until=$5 tt=$6 mpm_until=$7 mode=${8:-compare}
case_file=$source/cases/$name/case.toml
references=$source/tests/cases/references.txt
tt3=$(printf '%.3f' "$tt")

rm -rf "$work" && mkdir -p "$work"
cd "$work"
if [[ $fem_until == 0 ]]; then
  "$bin/fem-solve" "$case_file" -o fem --no-vtk --quiet > fem.log
else
  "$bin/fem-solve" "$case_file" -o fem --until "$fem_until" --no-vtk --quiet > fem.log
fi
"$bin/fem2mpm" "fem/fem_t$tt3.h5" -o particles.h5 --case "$case_file" --allow-inverted --quiet
"$bin/mpm-solve" "$case_file" -o mpm --particles particles.h5 --until "$mpm_until" --no-vtk \
  --quiet --threads 2 > mpm.log

# name=value pairs of everything measured
{
  # (the stress quality of the deposit at rest: not at rest this early in the run)
  "$bin/slide-metrics" measure "$case_file" mpm/mpm_final.h5 | grep -v '^stress_quality:' |
    tr ' ' '\n'
  awk -F, 'NR == 1 { for (i = 1; i <= NF; i++) c[$i] = i }
           END { print "fem_ke_over_pe0=" $c["ke_over_pe0"];
                 print "fem_jacobian_ratio_min=" $c["jacobian_ratio_min"] }' fem/fem_history.csv
  awk -F, 'NR == 1 { for (i = 1; i <= NF; i++) c[$i] = i }
           END { print "mpm_ke_over_pe0=" $c["ke_over_pe0"] }' mpm/mpm_history.csv
  /usr/bin/env awk -F'[:,]' '/"mass_fe"/ { fe = $2 } /"mass_particles"/ { p = $2 }
           END { printf "transfer_mass_error=%.3e\n", (p - fe) / fe }' particles.transfer.json
} > measured.txt

if [[ $mode == --record ]]; then
  grep -v '^\(bins\|strays\)=' measured.txt | sed "s/^\([^=]*\)=\(.*\)/$name \1 \2 TOLERANCE/"
  exit 0
fi

# references.txt: case key value tolerance, tolerance "abs:x" or "rel:x"
status=0
printf '%-18s %-24s %14s %14s %12s\n' case quantity measured reference tolerance
while read -r ref_case key value tolerance; do
  [[ $ref_case == "$name" ]] || continue
  measured=$(sed -n "s/^$key=//p" measured.txt)
  if [[ -z $measured ]]; then
    echo "$name: $key was not measured" >&2
    status=1
    continue
  fi
  verdict=$(awk -v m="$measured" -v r="$value" -v t="$tolerance" 'BEGIN {
      split(t, p, ":"); d = m - r; if (d < 0) d = -d;
      limit = (p[1] == "rel") ? p[2] * (r < 0 ? -r : r) : p[2];
      print (d <= limit && m == m) ? "ok" : "FAILED" }')
  printf '%-18s %-24s %14s %14s %12s %s\n' "$name" "$key" "$measured" "$value" "$tolerance" \
    "$verdict"
  [[ $verdict == ok ]] || status=1
done < <(grep -v '^#' "$references")
exit $status
