# Sourced by scripts/install_deps.sh and scripts/install_paraview_python.sh (not run on its own).
#
# install_missing_packages WHO PKG...
#   apt-get installs those PKGs that dpkg does not list as installed (with apt-get update first and
#   no recommends), after one line "WHO: installing <them>"; as root, else through sudo. Does nothing
#   when every PKG is installed.
install_missing_packages() {
  local who=$1 p
  shift
  local missing=()
  for p in "$@"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
  done
  [ ${#missing[@]} -gt 0 ] || return 0
  echo "$who: installing ${missing[*]}"
  local sudo=""
  [ "$(id -u)" = 0 ] || sudo="sudo"
  export DEBIAN_FRONTEND=noninteractive
  $sudo apt-get update -qq
  $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
}
