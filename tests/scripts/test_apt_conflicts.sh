#!/usr/bin/env bash
# tests/scripts/test_apt_conflicts.sh SOURCE_DIR: scripts/install_deps.sh on a machine with Debian's
# python3-paraview (which conflicts with python3-vtk9, needed by libvtk9-dev) stops before apt with one
# line naming the conflict and the way out, status non-zero; without that conflict apt is called.
# dpkg-query, apt-get and sudo are stand-ins on PATH: nothing is installed or removed.
set -uo pipefail
src=${1:?usage: test_apt_conflicts.sh SOURCE_DIR}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
mkdir "$work/bin"
# dpkg-query -W -f='${Status}' PKG: "install ok installed" for the packages listed in $FAKE_INSTALLED.
cat > "$work/bin/dpkg-query" <<'FAKE'
#!/usr/bin/env bash
pkg=${!#}
for p in $FAKE_INSTALLED; do
  if [ "$p" = "$pkg" ]; then printf 'install ok installed'; exit 0; fi
done
echo "dpkg-query: no packages found matching $pkg" >&2; exit 1
FAKE
printf '#!/usr/bin/env bash\necho "$*" >> "$FAKE_APT_LOG"\n' > "$work/bin/apt-get"
printf '#!/usr/bin/env bash\nexec "$@"\n' > "$work/bin/sudo"
chmod +x "$work/bin/"*
export PATH="$work/bin:$PATH" FAKE_APT_LOG="$work/apt.log"
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }

# run INSTALLED CMD...: runs CMD with that fake dpkg state; sets status, err (stderr), apt (apt-get calls).
run() {
  export FAKE_INSTALLED=$1
  shift
  : > "$FAKE_APT_LOG"
  "$@" > "$work/out" 2> "$work/err"
  status=$?
  err=$(cat "$work/err")
  apt=$(cat "$FAKE_APT_LOG")
}
lib() { bash -c '. "$0/scripts/apt_packages.sh" && install_missing_packages install_deps "$@"' "$src" "$@"; }

# 1. python3-paraview installed, libvtk9-dev to install: one line, status 1, apt never called.
run "python3-paraview cmake" lib cmake libvtk9-dev
[ "$status" -ne 0 ] || fail "conflict: status 0"
[ "$(printf '%s\n' "$err" | wc -l)" -eq 1 ] || fail "conflict: not one line on stderr: $err"
for w in python3-paraview python3-vtk9 libvtk9-dev "apt-get remove python3-paraview" install_paraview_python.sh; do
  [[ "$err" == *"$w"* ]] || fail "conflict: message lacks '$w': $err"
done
[ -z "$apt" ] || fail "conflict: apt-get was called: $apt"

# 2. The whole script (ParaView step off) on that machine: same line, non-zero exit, no apt.
run "python3-paraview" env MAGENC_WITH_PARAVIEW=0 "$src/scripts/install_deps.sh"
[ "$status" -ne 0 ] || fail "install_deps.sh: status 0 despite the conflict"
[[ "$err" == "install_deps: the installed python3-paraview conflicts with python3-vtk9"* ]] ||
  fail "install_deps.sh: unexpected stderr: $err"
[ "$(printf '%s\n' "$err" | wc -l)" -eq 1 ] || fail "install_deps.sh: not one line on stderr: $err"
[ -z "$apt" ] || fail "install_deps.sh: apt-get was called: $apt"

# 3. No python3-paraview: libvtk9-dev is installed through apt, status 0.
run "cmake" lib cmake libvtk9-dev
[ "$status" -eq 0 ] || fail "no conflict: status $status ($err)"
[[ "$apt" == *"install -y -qq --no-install-recommends libvtk9-dev"* ]] || fail "no conflict: apt log: $apt"

# 4. python3-paraview with packages it does not conflict with: installed as usual.
run "python3-paraview" lib gnuplot-nox
[ "$status" -eq 0 ] || fail "unrelated package: status $status ($err)"
[[ "$apt" == *"gnuplot-nox"* ]] || fail "unrelated package: apt log: $apt"

# 5. Everything already installed: nothing to do, no apt, even with python3-paraview present.
run "python3-paraview cmake" lib cmake
[ "$status" -eq 0 ] && [ -z "$apt" ] || fail "all installed: status $status, apt log: $apt"

[ "$failures" -eq 0 ] && echo "apt conflict checks passed" || exit 1
