#!/usr/bin/env bash
# The real samples in tests/data/external are byte-exact copies of the published files (each
# folder's SOURCE.md says where from): every file SHA256SUMS lists has the digest recorded there
# when it was copied, and no other file is there (README.md and SHA256SUMS aside). An edited
# sample, or a checkout that rewrote line endings (the .pos files mix LF and CRLF; .gitattributes
# keeps tests/data/** -text), fails here rather than as a puzzling reader test.
# Usage: check_external_data.sh DIR
set -euo pipefail
cd "$1"
sha256sum --check --strict --quiet SHA256SUMS
listed="$(awk '{print $2}' SHA256SUMS | sort)"
present="$(find . -type f ! -name SHA256SUMS ! -name README.md | sed 's|^\./||' | sort)"
if [ "$listed" != "$present" ]; then
  echo "check_external_data: files not listed in SHA256SUMS:" >&2
  comm -13 <(echo "$listed") <(echo "$present") >&2
  exit 1
fi
echo "check_external_data: $(echo "$listed" | wc -l) files match SHA256SUMS"
