#!/usr/bin/env bash
# rangecal set-up on Debian 12 (run as root, or with sudo available):
#   bash setup.sh demo   install what is missing, build (Release), run the demo
#   bash setup.sh test   install what is missing, build (Release), run every test
#   bash setup.sh build  install what is missing and build only
set -euo pipefail
cd "$(dirname "$0")"
what="${1:-build}"
BUILD_DIR="${BUILD_DIR:-build}"
JOBS="${JOBS:-$(nproc)}"

PKGS=(cmake g++ make libgeographiclib-dev geographiclib-tools libeigen3-dev libopencv-dev libceres-dev
      nlohmann-json3-dev libcli11-dev libgtest-dev libgmock-dev libbenchmark-dev libtbb-dev chromium)
missing=()
for p in "${PKGS[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "setup: installing missing Debian packages: ${missing[*]}"
  SUDO=""; [ "$(id -u)" -ne 0 ] && SUDO="sudo"
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi

cmake -S . -B "$BUILD_DIR" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$BUILD_DIR" -j "$JOBS"

case "$what" in
  build) ;;
  demo)
    "$BUILD_DIR/rangecal" demo --out "${DEMO_OUT:-demo-out}" ;;
  test)
    ctest --test-dir "$BUILD_DIR" --output-on-failure -j "$JOBS" ;;
  *) echo "usage: bash setup.sh [build|demo|test]" >&2; exit 2 ;;
esac
