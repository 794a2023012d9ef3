#!/usr/bin/env bash
# Longer fuzz runs for developers (docs/reliability.md "Fuzzing"), after `bash setup.sh fuzz` has
# built the targets (and assembled the corpora) in build-asan:
#   tests/fuzz/run_fuzz.sh SECONDS [FORMAT...]   each target (default: all) for SECONDS, one after
#                                                another, at low priority
# Logs go to build-asan/fuzz/logs/FORMAT.log; inputs that add coverage to build-asan/fuzz/work/FORMAT;
# reproducers to build-asan/fuzz/artifacts/FORMAT. Exits non-zero when any run reported a finding.
set -uo pipefail
cd "$(dirname "$0")/../.."
seconds="${1:?usage: tests/fuzz/run_fuzz.sh SECONDS [FORMAT...]}"
shift
build="${SAN_BUILD_DIR:-build-asan}"
dir="$build/fuzz"
formats=("$@")
if [ ${#formats[@]} -eq 0 ]; then
  for f in tests/fuzz/fuzz_*.cpp; do
    n="$(basename "$f" .cpp)"
    formats+=("${n#fuzz_}")
  done
fi
[ -d "$dir/corpus" ] || bash tests/fuzz/make_corpora.sh "$dir/corpus" "$build/tests/fuzz/fuzz_make_seeds" .
export ASAN_OPTIONS="${ASAN_OPTIONS:-halt_on_error=1:detect_leaks=1}"
export LSAN_OPTIONS="${LSAN_OPTIONS:-suppressions=$PWD/tests/sanitizer/lsan.supp}"
export UBSAN_OPTIONS="${UBSAN_OPTIONS:-halt_on_error=1:print_stacktrace=1}"
mkdir -p "$dir/logs"
failed=0
for f in "${formats[@]}"; do
  log="$dir/logs/$f.log"
  if nice -n 10 bash tests/fuzz/run_target.sh "$build/tests/fuzz/fuzz_$f" "$dir" "$f" \
    -max_total_time="$seconds" >"$log" 2>&1; then
    echo "fuzz_$f: $(grep -E '^stat::number_of_executed_units' "$log") $(grep -E '^#[0-9]+.*DONE' "$log" | tail -1)"
  else
    echo "fuzz_$f: FINDING (see $log and $dir/artifacts/$f/)"
    failed=1
  fi
done
exit $failed
