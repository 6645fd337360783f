# Sourced by scripts/install_deps.sh and scripts/install_paraview_python.sh (not run on its own).
#
# install_missing_packages WHO PKG...
#   apt-get installs those PKGs that dpkg does not list as installed (with apt-get update first and
#   no recommends), after one line "WHO: installing <them>"; as root, else through sudo. Does nothing
#   when every PKG is installed. Refuses (one line on stderr, status 1, nothing installed) when an
#   installed package conflicts with one to install (refuse_known_conflicts).
package_installed() {
  dpkg-query -W -f='${Status}' "$1" 2>/dev/null | grep -q "install ok installed"
}

# refuse_known_conflicts WHO PKG...: status 1 and one line naming the conflict and the way out when an
# installed package is known to conflict with one of the PKGs still to install; otherwise status 0.
#   Debian 12: python3-paraview Conflicts with python3-vtk9 (both ship the vtkmodules Python package),
#   and libvtk9-dev Depends on python3-vtk9, so apt can install neither while python3-paraview is
#   installed ("pkgProblemResolver::Resolve generated breaks").
refuse_known_conflicts() {
  local who=$1 p
  shift
  package_installed python3-paraview || return 0
  for p in "$@"; do
    case "$p" in
      libvtk9-dev|python3-vtk9)
        echo "$who: the installed python3-paraview conflicts with python3-vtk9, which $p needs" \
             "(libvtk9-dev builds magenc); remove it first (apt-get remove python3-paraview) and rerun:" \
             "scripts/install_paraview_python.sh then puts ParaView's Python beside libvtk9-dev" >&2
        return 1 ;;
    esac
  done
  return 0
}

install_missing_packages() {
  local who=$1 p
  shift
  local missing=()
  for p in "$@"; do
    package_installed "$p" || missing+=("$p")
  done
  [ ${#missing[@]} -gt 0 ] || return 0
  refuse_known_conflicts "$who" "${missing[@]}" || return 1
  echo "$who: installing ${missing[*]}"
  local sudo=""
  [ "$(id -u)" = 0 ] || sudo="sudo"
  export DEBIAN_FRONTEND=noninteractive
  $sudo apt-get update -qq
  $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
}
