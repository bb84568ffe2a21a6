# shellcheck shell=bash
# Sourced by scripts/sanitizers.sh and scripts/fuzz.sh: need_packages PKG... installs the Debian
# packages among PKG that are not installed yet (as root: apt-get update, then apt-get install
# --no-install-recommends); as another user it prints the exact sudo line and exits 1.
need_packages() {
  local p missing=()
  for p in "$@"; do
    [ "$(dpkg-query -W -f='${Status}' "$p" 2>/dev/null)" = "install ok installed" ] || missing+=("$p")
  done
  [ ${#missing[@]} -eq 0 ] && return 0
  if [ "$(id -u)" -eq 0 ]; then
    echo "$(basename "$0"): installing ${missing[*]}"
    apt-get update
    DEBIAN_FRONTEND=noninteractive apt-get install -y --no-install-recommends "${missing[@]}"
  else
    echo "$(basename "$0"): missing Debian packages. Install them with:" >&2
    echo "    sudo apt-get install -y --no-install-recommends ${missing[*]}" >&2
    exit 1
  fi
}

# What every hail build and test run needs (the same list as scripts/quickstart.sh test).
# shellcheck disable=SC2034  # used by the scripts that source this file
hail_test_packages=(build-essential cmake libtbb-dev libxsimd-dev libeigen3-dev catch2 nlohmann-json3-dev libcli11-dev libstb-dev)
