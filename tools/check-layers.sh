#!/usr/bin/env bash
# The include rules of the source tree (common/README.md), checked by the test
# style.layers: common/ is layered base < geometry < physics < settings < io < input < run, and a
# file may include only its own layer and the ones below; fem/, transfer/ and mpm/
# include common/ and never each other; no file-level loop (a module, a .hpp with its
# .cpp, includes a module that includes it back, at any remove); no solver or stage
# header includes the case reader (common/input/case_file*.hpp: the stages take typed
# settings, only the plans read a case). Prints every include that breaks a rule; with
# --picture the folder-to-folder include counts, with --readme checks common/README.md's
# copy of them. Exit 1 on any violation.
set -euo pipefail
cd "$(dirname "$0")/.."

layers=(base geometry physics settings io input run)
rank() {
  local i
  for i in "${!layers[@]}"; do
    [[ ${layers[$i]} == "$1" ]] && { echo "$i"; return; }
  done
  echo -1
}

violations=0
declare -A edges
modules=()
while IFS= read -r file; do
  from=${file%/*}
  while IFS= read -r included; do
    to=${included%/*}
    edges["$from -> $to"]=$((${edges["$from -> $to"]:-0} + 1))
    [[ ${file%.*} == "${included%.*}" ]] || modules+=("${file%.*} ${included%.*}")
    if [[ $file =~ ^(fem|mpm|transfer)/.*\.hpp$ && $included == common/input/case_file*.hpp ]]; then
      echo "$file includes $included: a stage takes typed settings, not the case file"
      violations=$((violations + 1))
    fi
    if [[ $from == common/* && $to == common/* ]]; then
      a=$(rank "${from#common/}")
      b=$(rank "${to#common/}")
      if ((a < 0 || b < 0 || b > a)); then
        echo "$file includes $included: ${to#common/} is above ${from#common/}"
        violations=$((violations + 1))
      fi
    elif [[ $from == common* && $to != common* ]]; then
      echo "$file includes $included: common/ depends on no stage"
      violations=$((violations + 1))
    elif [[ $from =~ ^(fem|mpm|transfer)$ && $to =~ ^(fem|mpm|transfer)$ && $from != "$to" ]]; then
      echo "$file includes $included: the stages depend on common/ only"
      violations=$((violations + 1))
    fi
  done < <(sed -n 's/^#include "\([a-z_/]*\.hpp\)".*/\1/p' "$file")
done < <(find common fem mpm transfer -name '*.[ch]pp' | sort)

# File-level loops: tsort orders the modules, or names a loop it finds.
if ! loops=$(printf '%s\n' "${modules[@]}" | tsort 2>&1 >/dev/null) || [[ -n $loops ]]; then
  echo "a loop of includes between modules: ${loops//$'\n'/; }"
  violations=$((violations + 1))
fi

# The folder-to-folder include counts, one line per including folder in layer order,
# its targets in layer order: the picture common/README.md shows (--readme checks it).
picture() {
  local order=(common/base common/geometry common/physics common/settings common/io common/input
    common/run fem transfer mpm)
  local from to line
  for from in "${order[@]}"; do
    line=""
    for to in "${order[@]}"; do
      [[ $from == "$to" || -z ${edges["$from -> $to"]:-} ]] && continue
      line+="${line:+, }$to (${edges["$from -> $to"]})"
    done
    [[ -n $line ]] && printf '%-15s -> %s\n' "$from" "$line"
  done
  return 0
}
case ${1:-} in
  --picture) picture ;;
  --readme)
    # The README's block after "include counts" must be the picture of this tree.
    if ! diff <(picture) <(awk '/^The include counts between folders/ { on = 1 }
        on && /^```$/ { if (++fences == 2) exit; next } on && fences == 1' common/README.md); then
      echo "common/README.md's include counts are not this tree's (tools/check-layers.sh --picture)"
      violations=$((violations + 1))
    fi
    ;;
esac
if ((violations > 0)); then
  echo "$violations include(s) break the layer rules (common/README.md)"
  exit 1
fi
