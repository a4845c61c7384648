#!/usr/bin/env bash
# The FE-phase study of fem/README.md: one case run with Mohr–Coulomb and with the
# pressure-independent multi-yield soil in FE, without and with its Rayleigh damping,
# under small-strain and updated-Lagrangian kinematics, each to fem.end_time (8 s for the
# columns). Prints one Markdown table row per run: first inversion (det J ≤ 0 at a
# corner, and (|J_t|/|J_0|)_min < 0), zone exit, and at the end the runout, the crest
# settlement H0 − H_c (docs/method.md §6, measured on an element-wise transfer of the final
# state) and the area ratio.
#
#   tools/fem-study.sh BUILD_DIR CASE_NAME [OUT_DIR]      e.g. tools/fem-study.sh build column-short
#   UNTIL=8 tools/fem-study.sh build column-tall           # to 8 s instead of fem.end_time
#
# The case's own [fem.damping] is "on"; "off" sets rayleigh_stiffness = 0. About 20 s
# per column case on 2 cores.
set -euo pipefail
[[ $# -ge 2 ]] || { sed -n '2,14s/^# \{0,1\}//p' "$0" >&2; exit 2; }
bin=$(cd "$1" && pwd)/bin
source=$(cd "$(dirname "$0")/.." && pwd)
case_name=$2
out=${3:-$(mktemp -d)}
mkdir -p "$out"
case_file=$source/cases/$case_name/case.toml
height=$(sed -n 's/^initial_height *= *\([0-9.]*\).*/\1/p' "$case_file")

echo "| FE model | damping | kinematics | first inversion (corner / (\|J_t\|/\|J_0\|)_min < 0) | zone exit | end time | runout (m) | crest settlement (m) | area ratio |"
echo "|---|---|---|---|---|---|---|---|---|"
for model in mohr-coulomb pressure-independent-multi-yield; do
  for damping in off on; do
    for kinematics in small-strain updated-lagrangian; do
      run=$out/$model-$damping-$kinematics
      mkdir -p "$run"
      variant=$run/case.toml
      sed -e "s/^fem_model = .*/fem_model = \"$model\"/" "$case_file" > "$variant"
      if [[ $damping == off ]]; then
        sed -i -e 's/^rayleigh_stiffness = .*/rayleigh_stiffness = 0.0/' "$variant"
      fi
      # Updated Lagrangian stops (with an error and a last checkpoint) at an inversion.
      "$bin/fem-solve" "$variant" -o "$run" --kinematics "$kinematics" --no-vtk --quiet \
        ${UNTIL:+--until "$UNTIL"} \
        > "$run/log.txt" 2>&1 || true
      summary=$run/fem_summary.txt
      value() { sed -n "s/^$1 = //p" "$summary" 2>/dev/null; }
      last=$(ls "$run"/fem_t*.h5 | sort -t t -k 3 -g | tail -1)
      end=$(basename "$last" .h5 | sed 's/^fem_t//')
      "$bin/fem2mpm" "$last" -o "$run/particles_end.h5" --case "$variant" \
        --stress-interpolation element --allow-inverted --quiet > /dev/null 2>&1 || true
      measure=$("$bin/slide-metrics" measure "$variant" "$run/particles_end.h5" 2>/dev/null || true)
      runout=$(sed -n 's/.* runout=\([^ ]*\).*/\1/p' <<< "$measure")
      crest=$(sed -n 's/.*crest_height=\([^ ]*\).*/\1/p' <<< "$measure")
      settlement=$(awk -v h="$height" -v c="$crest" 'BEGIN { if (c == "") print ""; else printf "%.1f", h - c }')
      area=$(awk -F, -v t="$end" 'NR == 1 { for (i = 1; i <= NF; ++i) if ($i == "area_ratio") col = i; next }
                                  { if ($1 + 0 <= t + 1e-9) a = $col } END { printf "%.3f", a }' "$run/fem_history.csv")
      printf '| %s | %s | %s | %s / %s s | %s s | %s s | %.1f | %s | %s |\n' "$model" "$damping" \
        "$kinematics" "$(value first_time_inverted)" "$(value first_time_jacobian_ratio_negative)" \
        "$(value zone_exit_time)" "$end" "${runout:-nan}" "$settlement" "$area"
    done
  done
done
