#!/usr/bin/env bash
# One libFuzzer run of a rangecal fuzz target over its assembled corpus (docs/reliability.md
# "Fuzzing"). Usage: run_target.sh FUZZER FUZZ_DIR FORMAT [libFuzzer options...]
#   FUZZ_DIR/corpus/FORMAT     seeds (make_corpora.sh), read only
#   FUZZ_DIR/work/FORMAT       inputs this run adds (new coverage)
#   FUZZ_DIR/artifacts/FORMAT  crash-*, timeout-*, oom-*, leak-* reproducers
#   FUZZ_DIR/tmp               scratch files of the path-based readers (TMPDIR)
# Exits non-zero when libFuzzer reports anything.
set -euo pipefail
fuzzer="$1" dir="$2" format="$3"
shift 3
here="$(cd "$(dirname "$0")" && pwd)"
mkdir -p "$dir/work/$format" "$dir/artifacts/$format" "$dir/tmp" "$dir/corpus/$format"
dict=()
[ -f "$here/dict/$format.dict" ] && dict=("-dict=$here/dict/$format.dict")
export TMPDIR="$dir/tmp"
export ASAN_OPTIONS="halt_on_error=1:detect_leaks=1${ASAN_OPTIONS:+:$ASAN_OPTIONS}"
export LSAN_OPTIONS="suppressions=$here/../sanitizer/lsan.supp${LSAN_OPTIONS:+:$LSAN_OPTIONS}"
export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1${UBSAN_OPTIONS:+:$UBSAN_OPTIONS}"
exec "$fuzzer" -timeout=10 -rss_limit_mb=2048 -print_final_stats=1 \
  -artifact_prefix="$dir/artifacts/$format/" "${dict[@]}" "$@" "$dir/work/$format" "$dir/corpus/$format"
