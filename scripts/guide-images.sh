#!/usr/bin/env bash
# Regenerates the user guide's screenshots (docs/guide/src/img/) from runs of two shipped
# problems, the beam on its foundation and the cylinder indenter:
#
#     scripts/guide-images.sh [path to an mlpg-contact binary; default target/release/mlpg-contact]
#
# Each image is a run's plot copied byte for byte (tests/cli.rs, every_shipped_problem_runs,
# fails when one differs from a run of the tested binary: rerun this script after a change of
# the plots or of these problems' answers).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
bin=$(realpath "${1:-$root/target/release/mlpg-contact}")
img="$root/docs/guide/src/img"
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
mkdir -p "$img"
# The list (problem, plot, image) below is read by tests/cli.rs too.
while read -r problem plot image; do
    [ -d "$out/$problem" ] || "$bin" "$root/problems/$problem.toml" --out "$out/$problem" --quiet
    cp "$out/$problem/plots/$plot" "$img/$image"
    echo "docs/guide/src/img/$image  <-  problems/$problem.toml, plots/$plot"
done <<'LIST'
beam_on_foundation contact_pressure.png beam_contact_pressure.png
beam_on_foundation deformed.png beam_deformed.png
cylinder_indenter contact_pressure.png indenter_contact_pressure.png
cylinder_indenter deformed.png indenter_deformed.png
LIST
