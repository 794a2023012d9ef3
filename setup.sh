#!/usr/bin/env bash
# rangecal set-up on Debian 12 (run as root, or with sudo available):
#   bash setup.sh demo   install what is missing, build (Release), run the demo
#   bash setup.sh test   install what is missing, build (Release), run every test
#   bash setup.sh build  install what is missing and build only
#   bash setup.sh sanitize  the unit tests built with AddressSanitizer + UndefinedBehaviorSanitizer
#                           (clang, folder build-asan) and run (docs/reliability.md "Sanitizers")
#   bash setup.sh fuzz      the libFuzzer targets built in build-asan and each run briefly over its
#                           seed corpus (FUZZ_SECONDS, default 20) (docs/reliability.md "Fuzzing")
set -euo pipefail
cd "$(dirname "$0")"
what="${1:-build}"
BUILD_DIR="${BUILD_DIR:-build}"
JOBS="${JOBS:-$(nproc)}"

PKGS=(cmake g++ make libgeographiclib-dev geographiclib-tools libeigen3-dev libopencv-dev libceres-dev
      nlohmann-json3-dev libcli11-dev libgtest-dev libgmock-dev libbenchmark-dev libtbb-dev chromium
      clang libclang-rt-14-dev llvm-14)  # the last three: sanitizer and fuzz builds (libFuzzer, llvm-symbolizer)
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

# The sanitizer folder: clang, -O1 -g, ASan + UBSan (no recovery) everywhere and libFuzzer coverage
# on the libraries, so that one compile serves both the sanitizer unit tests and the fuzz targets.
SAN_BUILD_DIR="${SAN_BUILD_DIR:-build-asan}"
san_configure() {
  cmake -S . -B "$SAN_BUILD_DIR" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_COMPILER=clang++ \
    -DRANGECAL_SANITIZE=ON -DRANGECAL_FUZZ=ON -DRANGECAL_BUILD_BENCHMARKS=OFF \
    -DRANGECAL_FUZZ_SECONDS="${FUZZ_SECONDS:-20}" >/dev/null
}
export ASAN_OPTIONS="halt_on_error=1:detect_leaks=1"
export LSAN_OPTIONS="suppressions=$PWD/tests/sanitizer/lsan.supp:print_suppressions=0"
export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1"
[ -x /usr/lib/llvm-14/bin/llvm-symbolizer ] && export ASAN_SYMBOLIZER_PATH=/usr/lib/llvm-14/bin/llvm-symbolizer
# Unit tests left out of the sanitizer run, and why: see docs/reliability.md "Sanitizers".
SAN_EXCLUDE="${SAN_EXCLUDE-^$}"

case "$what" in
  build | demo | test)
    cmake -S . -B "$BUILD_DIR" -DCMAKE_BUILD_TYPE=Release >/dev/null
    cmake --build "$BUILD_DIR" -j "$JOBS" ;;
esac

case "$what" in
  build) ;;
  demo)
    "$BUILD_DIR/rangecal" demo --out "${DEMO_OUT:-demo-out}" ;;
  test)
    ctest --test-dir "$BUILD_DIR" --output-on-failure -j "$JOBS" ;;
  sanitize)
    san_configure
    unit_targets=()
    for f in tests/unit/*/*_test.cpp; do
      n="$(basename "$f" .cpp)"
      unit_targets+=("test_${n%_test}")
    done
    cmake --build "$SAN_BUILD_DIR" -j "$JOBS" --target "${unit_targets[@]}"
    ctest --test-dir "$SAN_BUILD_DIR" -L unit -E "$SAN_EXCLUDE" --output-on-failure -j "$JOBS" ;;
  fuzz)
    san_configure
    cmake --build "$SAN_BUILD_DIR" -j "$JOBS" --target fuzz_targets
    ctest --test-dir "$SAN_BUILD_DIR" -L fuzz --output-on-failure -j "$JOBS" ;;
  *) echo "usage: bash setup.sh [build|demo|test|sanitize|fuzz]" >&2; exit 2 ;;
esac
