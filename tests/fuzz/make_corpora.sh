#!/usr/bin/env bash
# Assembles the fuzz seed corpora (docs/reliability.md "Fuzzing") into OUT/<format>/ from
#   tests/fuzz/seeds/<format>/   tiny checked-in seeds and crash reproducers (regression seeds),
#   fuzz_make_seeds              tiny .cine, .mraw/.cihx, .cih and DataFlash files it writes,
#   config/examples/*.json       mission configs and scenarios,
#   tests/data/external/         the real samples (RTKLIB .pos, PX4 .ulg, .cine, .cihx/.mraw),
#                                cut to their first lines or bytes so that runs stay fast.
# Usage: make_corpora.sh OUT MAKE_SEEDS SOURCE_DIR
set -euo pipefail
out="$1" make_seeds="$2" src="$3" ext="$3/tests/data/external"
rm -rf "$out"
mkdir -p "$out"
cp -r "$src/tests/fuzz/seeds/." "$out/"
"$make_seeds" "$out"
for f in "$src"/config/examples/*.json; do
  mkdir -p "$out/mission_config" "$out/scenario"
  cp "$f" "$out/mission_config/"
  cp "$f" "$out/scenario/"
done
sep=$'\n--rangecal-fuzz-mraw--\n'  # as in fuzz_photron_mraw.cpp
mkdir -p "$out/rtklib_pos" "$out/px4_ulog" "$out/cine" "$out/photron_header" "$out/photron_mraw"
for f in "$ext"/gnss/pos/*.pos; do head -n 40 "$f" >"$out/rtklib_pos/$(basename "$f")"; done
for f in "$ext"/px4-ulog/*.ulg; do head -c 131072 "$f" >"$out/px4_ulog/$(basename "$f")"; done
for f in "$ext"/phantom-cine/*.cine; do head -c 65536 "$f" >"$out/cine/$(basename "$f")"; done
for f in "$ext"/photron-mraw/*.cihx; do
  cp "$f" "$out/photron_header/"
  { printf x; cat "$f"; printf '%s' "$sep"; head -c 4096 "${f%.cihx}.mraw"; } >"$out/photron_mraw/$(basename "$f")"
done
echo "make_corpora: $(find "$out" -type f | wc -l) seeds in $(find "$out" -mindepth 1 -maxdepth 1 -type d | wc -l) corpora"
