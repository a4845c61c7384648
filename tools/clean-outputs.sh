#!/usr/bin/env bash
# `make clean` of the case pipelines: removes what a pipeline made in OUT and nothing
# else, and OUT itself when that leaves it empty.
#
#   tools/clean-outputs.sh OUT ENTRY...    ENTRY: a file, folder or glob relative to OUT
#
# Refused, with one line and status 2, before anything is removed: an empty OUT, the root,
# the home folder, the repository or a folder above it, and a folder the pipeline has not
# marked as its own (OUT/.slide-outputs, which it writes when it first writes there; an
# OUT of an earlier version is recognised by the case.mk the pipeline keeps in it), or
# one where a run is still writing (a live process holds a .slide-lock in it). An OUT that
# does not exist is nothing to clean.
set -euo pipefail
out=${1-}
shift || true
root=$(cd "$(dirname "$0")/.." && pwd -P)
refuse() { echo "make clean: $*; nothing removed" >&2; exit 2; }

[[ -n $out ]] || refuse "OUT is empty"
[[ -e $out ]] || exit 0
[[ -d $out ]] || refuse "OUT=$out is not a folder"
real=$(cd "$out" && pwd -P)
home=$(cd ~ 2>/dev/null && pwd -P || echo /nonexistent)
[[ $real != / ]] || refuse "OUT=$out is the root folder"
[[ $real != "$home" ]] || refuse "OUT=$out is the home folder"
case "$root/" in
  "$real"/*) refuse "OUT=$out is the repository or holds it ($root)" ;;
esac
if [[ ! -f $real/.slide-outputs && ! -f $real/case.mk ]]; then
  refuse "OUT=$out has no .slide-outputs: not a folder the pipeline wrote"
fi
# A run still writing in OUT (a live process holds a .slide-lock there, common/run/
# output_lock.hpp) keeps its files.
host=$(hostname)
while IFS= read -r lock; do
  read -r pid start lock_host < "$lock" || true
  [[ ${lock_host:-} == "$host" && ${pid:-} =~ ^[0-9]+$ && -r /proc/$pid/stat ]] || continue
  stat=$(< "/proc/$pid/stat")
  fields=(${stat##*) })
  if [[ ${fields[19]} == "${start:-}" ]]; then
    refuse "a run (pid $pid) is writing in $(dirname "$lock")"
  fi
done < <(find "$real" -name .slide-lock -type f 2>/dev/null)
shopt -s nullglob
for pattern in "$@"; do
  for entry in "$real"/$pattern; do rm -rf -- "$entry"; done
done
rm -f -- "$real/.slide-outputs"
rmdir -- "$real" 2>/dev/null || true
