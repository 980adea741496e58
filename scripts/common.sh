# Shared by the scripts that build (scripts/test, scripts/demo, ...): install what is missing,
# configure, build. Sourcing it builds nothing.
set -euo pipefail

ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
BUILD="${WMRA_BUILD_DIR:-$ROOT/build/host}"

# Debian packages the project needs: the toolchain, simavr, Eigen and GoogleTest; python3 for the
# figures of scripts/bench, scripts/demo and scripts/performance-report
PACKAGES=(cmake make g++ pkg-config gcc-avr binutils-avr avr-libc avrdude simavr libsimavr-dev libelf-dev
          libeigen3-dev libgtest-dev python3)
# and for the tests only: headless Chromium (about 350 MB) for the report checks (scripts/check-report)
TEST_PACKAGES=(chromium)

# install_missing_packages [EXTRA_PACKAGE...]: PACKAGES and the extra ones, those not installed yet
install_missing_packages() {
  local missing=()
  for p in "${PACKAGES[@]}" "$@"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
  done
  [ ${#missing[@]} -eq 0 ] && return 0
  echo "Installing: ${missing[*]}"
  local sudo=""
  [ "$(id -u)" -ne 0 ] && sudo="sudo"
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq "${missing[@]}" >/dev/null
}

build_all() {
  cmake -S "$ROOT" -B "$BUILD" -DCMAKE_BUILD_TYPE=RelWithDebInfo >/dev/null
  cmake --build "$BUILD" -j"$(nproc)"
}

# build_targets TARGET...: configures, then builds only those targets, printing the build's
# progress (avr_images is the whole AVR sub-build: the firmware image and the test images,
# seconds beside the host side)
build_targets() {
  echo "== configuring $BUILD"
  cmake -S "$ROOT" -B "$BUILD" -DCMAKE_BUILD_TYPE=RelWithDebInfo >/dev/null
  echo "== building $*"
  cmake --build "$BUILD" -j"$(nproc)" --target "$@"
}
