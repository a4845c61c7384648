#!/usr/bin/env bash
# tools/install-deps.sh against a package database it cannot change: fake dpkg-query and
# apt-get first on PATH. With python3-paraview installed and libvtk9-dev missing it must
# say so in one line and exit 1 before calling apt-get (which would fail with apt's
# "generated breaks"); with everything present it must exit 0 without calling apt-get.
#
#   install_deps_test.sh SOURCE_DIR WORK_DIR
set -euo pipefail
source=$1 work=$2
rm -rf "$work" && mkdir -p "$work/bin"
fail() { echo "install_deps_test: $*" >&2; exit 1; }

# dpkg-query -W -f=... NAME: "install ok installed" unless NAME is listed in $work/absent.
cat > "$work/bin/dpkg-query" <<'FAKE'
#!/usr/bin/env bash
name=${!#}
grep -qx "$name" "$FAKE_DB/absent" 2>/dev/null && exit 1
grep -qx "$name" "$FAKE_DB/present-extra" 2>/dev/null && { printf 'install ok installed'; exit 0; }
[[ $name == python3-paraview ]] && exit 1
printf 'install ok installed'
FAKE
printf '#!/bin/sh\necho "apt-get called: $*" >> "$FAKE_DB/apt.log"\nexit 100\n' > "$work/bin/apt-get"
chmod +x "$work/bin/dpkg-query" "$work/bin/apt-get"
export FAKE_DB=$work PATH="$work/bin:$PATH"

# Everything present: nothing to do.
"$source/tools/install-deps.sh" > "$work/present.log" 2>&1 || fail "exit $? with every package present"
[[ ! -e $work/apt.log ]] || fail "apt-get called with every package present"

# python3-paraview installed, libvtk9-dev missing: one line naming both, exit 1, no apt-get.
echo libvtk9-dev > "$work/absent"
echo python3-paraview > "$work/present-extra"
status=0
"$source/tools/install-deps.sh" > "$work/conflict.out" 2> "$work/conflict.err" || status=$?
[[ $status == 1 ]] || fail "exit $status with the python3-paraview conflict (expected 1)"
[[ $(wc -l < "$work/conflict.err") == 1 ]] || { cat "$work/conflict.err"; fail "not one line"; }
grep -q 'python3-paraview is installed and conflicts with libvtk9-dev' "$work/conflict.err" \
  || { cat "$work/conflict.err"; fail "the message does not name the conflict"; }
grep -q "apt-get remove python3-paraview" "$work/conflict.err" || fail "the message does not say what to do"
[[ ! -e $work/apt.log ]] || fail "apt-get called despite the conflict"
echo "install_deps_test: present and python3-paraview-conflict checks passed"
