#!/usr/bin/env bash
# Runs an mlpg-contact binary on every problems/*.toml (and `--compare` on the beam) and prints
# one "sha256  file" line per output file, with the wall-clock timings removed first (the
# "timings" objects of summary.json and the total_seconds row of compare.csv/compare.md), so
# that two builds can be compared byte for byte:
#
#     scripts/output-digest.sh target/release/mlpg-contact > after.txt
#
# scripts/check-outputs.sh does this for a git revision and the working tree and diffs them.
set -euo pipefail
bin=$(realpath "$1")
root=$(cd "$(dirname "$0")/.." && pwd)
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
for p in "$root"/problems/*.toml; do
    name=$(basename "$p" .toml)
    "$bin" "$p" --out "$out/$name" --quiet
done
"$bin" "$root/problems/beam_on_foundation.toml" --out "$out/compare" --compare --quiet
cd "$out"
find . -type f | LC_ALL=C sort | while read -r f; do
    case "$f" in
    */summary.json)
        # Drop every `"timings": { … }` block (any indentation).
        awk '
            skip == 0 && /^ *"timings": \{/ { match($0, /^ */); indent = RLENGTH; skip = 1; next }
            skip == 1 { match($0, /^ */); if (RLENGTH == indent && $0 ~ /^ *\},?$/) skip = 0; next }
            { print }
        ' "$f" | sha256sum | sed "s|-|$f|"
        ;;
    */compare.csv | */compare.md)
        grep -v 'total_seconds' "$f" | sha256sum | sed "s|-|$f|"
        ;;
    *)
        sha256sum "$f"
        ;;
    esac
done
