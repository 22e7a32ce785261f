#!/usr/bin/env bash
# Checks that the working tree's binary writes byte-identical outputs (timings aside) to the
# binary built from a git revision, on every shipped problem:
#
#     scripts/check-outputs.sh 657cb0f
#
# The revision is built in a temporary worktree (sharing this checkout's target directory for
# the dependencies); exit status 0 when every output file agrees, 1 with the diff otherwise.
set -euo pipefail
rev=${1:?usage: scripts/check-outputs.sh <git revision>}
root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"
target=${CARGO_TARGET_DIR:-$root/target}
work=$(mktemp -d)
trap 'git worktree remove --force "$work/tree" >/dev/null 2>&1 || true; rm -rf "$work"' EXIT
git worktree add --detach "$work/tree" "$rev" >/dev/null
CARGO_TARGET_DIR="$target/check-outputs" cargo build --release --quiet --manifest-path "$work/tree/Cargo.toml"
cp "$target/check-outputs/release/mlpg-contact" "$work/before"
cargo build --release --quiet
cp "$target/release/mlpg-contact" "$work/after"
scripts/output-digest.sh "$work/before" > "$work/before.txt"
scripts/output-digest.sh "$work/after" > "$work/after.txt"
if diff "$work/before.txt" "$work/after.txt"; then
    echo "identical: $(wc -l < "$work/after.txt") output files of $(git rev-parse --short "$rev") and the working tree"
else
    echo "outputs differ between $(git rev-parse --short "$rev") and the working tree" >&2
    exit 1
fi
