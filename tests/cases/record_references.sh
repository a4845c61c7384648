#!/usr/bin/env bash
# Re-measures the key numbers of tests/cases/references.txt, keeping every key's
# tolerance and the file's comments: for a deliberate change of the physics or of the
# transfer (e.g. another stress interpolation), which moves the references.
#
#   tests/cases/record_references.sh BUILD_DIR [CASE ...]           # prints the new file
#   tests/cases/record_references.sh BUILD_DIR --write [CASE ...]   # rewrites references.txt
#
# Without CASE every case is measured. The cuts (FE end, t_T, MPM end) are those of the
# slide_case_test lines of tests/cases/CMakeLists.txt, the chain that of case_chain.sh.
# Review `git diff tests/cases/references.txt` and say in the commit why the numbers moved.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
source=$(cd "$here/../.." && pwd)
references=$here/references.txt
[[ $# -ge 1 ]] || { sed -n '2,12s/^# \{0,1\}//p' "$0" >&2; exit 2; }
build=$(cd "$1" && pwd)
shift
write=no
if [[ ${1:-} == --write ]]; then write=yes; shift; fi

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
: > "$work/recorded.txt"
found=0
while read -r name fem_until tt mpm_until; do
  if [[ $# -gt 0 && " $* " != *" $name "* ]]; then continue; fi
  found=$((found + 1))
  echo "record_references: $name (FE to $fem_until s, t_T = $tt s, MPM to $mpm_until s)" >&2
  "$here/case_chain.sh" "$build/bin" "$source" "$work/$name" "$name" "$fem_until" "$tt" \
    "$mpm_until" --record >> "$work/recorded.txt"
done < <(sed -n 's/^slide_case_test(\([^ ]*\) \([^ ]*\) \([^ ]*\) \([^ )]*\))$/\1 \2 \3 \4/p' \
           "$here/CMakeLists.txt")
[[ $found -gt 0 ]] || { echo "record_references: no such case: $*" >&2; exit 1; }

# Replace the value of every recorded (case, key); everything else stays as it is.
awk 'NR == FNR { value[$1 " " $2] = $3; next }
     /^#/ || NF < 4 { print; next }
     ($1 " " $2) in value { $3 = value[$1 " " $2]; delete value[$1 " " $2] }
     { print }
     END { for (k in value) print "record_references: new key " k " has no tolerance yet" > "/dev/stderr" }' \
  "$work/recorded.txt" "$references" > "$work/references.txt"

if [[ $write == yes ]]; then
  cp "$work/references.txt" "$references"
  echo "record_references: wrote $references" >&2
else
  cat "$work/references.txt"
fi
