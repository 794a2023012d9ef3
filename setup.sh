#!/usr/bin/env bash
# rangecal set-up on Debian 12 (run as root, or with sudo available):
#   bash setup.sh demo      run-time packages, build the rangecal program only (Release), run the demo
#   bash setup.sh test      also the test packages; build the program and the tests (Release), run
#                           every test
#   bash setup.sh bench     the Google Benchmark targets of tests/bench (Release, folder build);
#                           run them as build/tests/bench_<name> (docs/performance.md)
#   bash setup.sh build     run-time packages, build the rangecal program only
#   bash setup.sh sanitize  the unit tests built with AddressSanitizer + UndefinedBehaviorSanitizer
#                           (clang, folder build-asan) and run (docs/reliability.md "Sanitizers")
#   bash setup.sh fuzz      the libFuzzer targets built in build-asan and each run briefly over its
#                           seed corpus (FUZZ_SECONDS, default 10; FUZZ_SEED, default 1, 0 = random)
#                           (docs/reliability.md "Fuzzing")
# The console gets one line per step; the package manager's and the compiler's output go to
# setup-logs/<step>.log, whose tail is printed when a step fails.
set -euo pipefail
cd "$(dirname "$0")"
what="${1:-build}"
BUILD_DIR="${BUILD_DIR:-build}"
JOBS="${JOBS:-$(nproc)}"
LOG_DIR="${LOG_DIR:-setup-logs}"
mkdir -p "$LOG_DIR"

# What the rangecal program needs to build and run.
RUNTIME_PKGS=(cmake g++ make ninja-build libgeographiclib-dev libeigen3-dev libopencv-dev libceres-dev
              nlohmann-json3-dev libcli11-dev libtbb-dev libfmt-dev)
# What the tests add: GoogleTest, Google Benchmark, GeographicLib's CartConvert (an independent
# oracle), Chromium (renders report.html headless), clang-format (the code_format test).
TEST_PKGS=(libgtest-dev libgmock-dev libbenchmark-dev geographiclib-tools chromium clang-format)
# The sanitizer and fuzz builds: clang, its sanitizer and libFuzzer runtimes, llvm-symbolizer.
SAN_PKGS=(clang libclang-rt-14-dev llvm-14)

# step NAME COMMAND...: one console line, the output in the step's log, its tail on failure.
step() {
  local name="$1"
  shift
  local log="$LOG_DIR/$name.log"
  local t0=$SECONDS
  printf 'setup: %-10s ... ' "$name"
  if "$@" >"$log" 2>&1; then
    printf 'ok (%d s)\n' $((SECONDS - t0))
  else
    local rc=$?
    printf 'FAILED (exit %d after %d s)\n' "$rc" $((SECONDS - t0))
    echo "setup: the last lines of $log:" >&2
    tail -n 30 "$log" >&2
    exit "$rc"
  fi
}

install_missing() {
  local missing=()
  for p in "$@"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
  done
  if [ ${#missing[@]} -eq 0 ]; then
    echo "all packages present"
    return 0
  fi
  echo "installing: ${missing[*]}"
  local sudo=""
  [ "$(id -u)" -ne 0 ] && sudo="sudo"
  $sudo apt-get update &&
    DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y --no-install-recommends "${missing[@]}"
}

# The Release folder: the program alone for the demo, everything for the tests.
# Ninja compiles a target's files while the libraries below it are still building (make finishes
# each library first, leaving a core idle at every layer's last file), which keeps both cores busy:
# CI time. A folder configured earlier with another generator keeps it.
generator_args() {
  local cache="$1/CMakeCache.txt"
  if [ -f "$cache" ] && ! grep -q '^CMAKE_GENERATOR:INTERNAL=Ninja$' "$cache"; then return 0; fi
  echo "-G Ninja"
}

# The benchmarks are their own step (`bench`): the tests do not need them, and CI builds them
# last, with what is left of its time.
release_build() {
  local with_tests="$1" with_benchmarks="$2"
  shift 2
  # shellcheck disable=SC2046
  cmake -S . -B "$BUILD_DIR" $(generator_args "$BUILD_DIR") -DCMAKE_BUILD_TYPE=Release \
    -DRANGECAL_BUILD_TESTS="$with_tests" \
    -DRANGECAL_BUILD_BENCHMARKS="$with_benchmarks" &&
    cmake --build "$BUILD_DIR" -j "$JOBS" "$@"
}

# The sanitizer folder: clang, -O1, ASan + UBSan (no recovery) everywhere and libFuzzer coverage
# on the libraries, so that one compile serves both the sanitizer unit tests and the fuzz targets.
SAN_BUILD_DIR="${SAN_BUILD_DIR:-build-asan}"
san_configure() {
  # shellcheck disable=SC2046
  cmake -S . -B "$SAN_BUILD_DIR" $(generator_args "$SAN_BUILD_DIR") -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    -DCMAKE_CXX_COMPILER=clang++ \
    -DRANGECAL_SANITIZE=ON -DRANGECAL_FUZZ=ON -DRANGECAL_BUILD_BENCHMARKS=OFF \
    -DRANGECAL_FUZZ_SECONDS="${FUZZ_SECONDS:-10}" -DRANGECAL_FUZZ_SEED="${FUZZ_SEED:-1}"
}
export ASAN_OPTIONS="halt_on_error=1:detect_leaks=1"
export LSAN_OPTIONS="suppressions=$PWD/tests/sanitizer/lsan.supp:print_suppressions=0"
export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1"
[ -x /usr/lib/llvm-14/bin/llvm-symbolizer ] && export ASAN_SYMBOLIZER_PATH=/usr/lib/llvm-14/bin/llvm-symbolizer
# The sanitizer job runs the unit tests labelled `sanitize` (the input layers config, gnss, vision; the rule is
# declared once, with the reason, in tests/CMakeLists.txt) less the two detector tests that scan a
# thousand full frames and the OpenCV / DLT export fits (numerical fits of a calibrated camera,
# 15–95 s each under ASan); docs/reliability.md "Sanitizers" gives the measured times.
SAN_EXCLUDE="${SAN_EXCLUDE-^LampDetector\.(NoFalseLampInThousandLampFreeFrames|CentroidAccuracyUnsaturatedSnr20)$|^(OpenCvCameraExport|DltExport)\.}"

case "$what" in
  demo | build)
    step packages install_missing "${RUNTIME_PKGS[@]}"
    step build release_build OFF OFF --target rangecal
    if [ "$what" = demo ]; then
      echo "setup: demo       ... (rangecal demo --out ${DEMO_OUT:-demo-out})"
      "$BUILD_DIR/rangecal" demo --out "${DEMO_OUT:-demo-out}"
    fi ;;
  test)
    step packages install_missing "${RUNTIME_PKGS[@]}" "${TEST_PKGS[@]}"
    step build release_build ON OFF
    echo "setup: tests      ... (ctest; the full log is $BUILD_DIR/Testing/Temporary/LastTest.log)"
    ctest --test-dir "$BUILD_DIR" --output-on-failure -j "$JOBS" ;;
  sanitize)
    step packages install_missing "${RUNTIME_PKGS[@]}" "${TEST_PKGS[@]}" "${SAN_PKGS[@]}"
    step configure-asan san_configure
    step build-asan cmake --build "$SAN_BUILD_DIR" -j "$JOBS" --target sanitizer_tests
    echo "setup: sanitize   ... (ctest -L sanitize -E '$SAN_EXCLUDE')"
    ctest --test-dir "$SAN_BUILD_DIR" -L sanitize -E "$SAN_EXCLUDE" --output-on-failure -j "$JOBS" ;;
  fuzz)
    step packages install_missing "${RUNTIME_PKGS[@]}" "${TEST_PKGS[@]}" "${SAN_PKGS[@]}"
    step configure-asan san_configure
    step build-fuzz cmake --build "$SAN_BUILD_DIR" -j "$JOBS" --target fuzz_targets
    echo "setup: fuzz       ... (ctest -L fuzz, ${FUZZ_SECONDS:-10} s per target)"
    ctest --test-dir "$SAN_BUILD_DIR" -L fuzz --output-on-failure -j "$JOBS" ;;
  bench)
    step packages install_missing "${RUNTIME_PKGS[@]}" "${TEST_PKGS[@]}"
    step build-bench release_build ON ON --target benchmarks
    echo "setup: benchmarks built: $(ls "$BUILD_DIR"/tests/bench_* | tr '\n' ' ')" ;;
  *) echo "usage: bash setup.sh [demo|test|build|sanitize|fuzz|bench]" >&2; exit 2 ;;
esac
