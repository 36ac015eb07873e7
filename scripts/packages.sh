# Sourced by the scripts: installs the Debian packages a step needs when they are missing.
# Only the Debian archive is needed; nothing is downloaded at build time.

BUILD_PACKAGES=(cmake make g++ libeigen3-dev libboost-dev libboost-program-options-dev
                libsuitesparse-dev nlohmann-json3-dev
                python3-dev pybind11-dev python3-numpy)  # the Python module
TEST_PACKAGES=(libgtest-dev libbenchmark-dev clang-format universal-ctags python3-pytest python3-scipy
               python3-distributed python3-matplotlib python3-meshio
               python3-vtk9 xvfb xauth)  # the ParaView recipe rendered headless

ensure_packages() {
  local missing=()
  for package in "$@"; do
    dpkg-query -W -f='${Status}' "$package" 2>/dev/null | grep -q "install ok installed" ||
      missing+=("$package")
  done
  [ ${#missing[@]} -eq 0 ] && return 0
  echo "installing: ${missing[*]}" >&2
  local sudo=()
  if [ "$(id -u)" -ne 0 ]; then
    command -v sudo >/dev/null || { echo "need root (or sudo) to install: ${missing[*]}" >&2; return 1; }
    sudo=(sudo)
  fi
  "${sudo[@]}" apt-get update -qq
  DEBIAN_FRONTEND=noninteractive "${sudo[@]}" apt-get install -y -qq --no-install-recommends \
    "${missing[@]}" >/dev/null
}
