#!/usr/bin/env python3
"""Lists the crates that `cargo test --release` and the Python wheel's build compile differently.

Both builds share `target/`; a crate built with other features (or another profile) in the
second build is compiled again, and so is everything above it (serde's dependants, plotters,
mlpg-contact). `tools/workspace-hack` asks both builds for the union of the features; this
script shows what is left to add there. It reads Cargo's unit graphs (`--unit-graph`, an
unstable flag: RUSTC_BOOTSTRAP=1 is set for these two commands only, which build nothing).

Usage: python3 scripts/feature-alignment.py   (from the repository's root; exit 1 when a
shared crate differs)
"""
import json
import os
import subprocess
import sys

COMMANDS = {
    "cargo test --release": ["cargo", "test", "--release", "--no-run"],
    "the wheel (maturin)": [
        "cargo", "rustc", "--profile", "release", "--manifest-path", "python/Cargo.toml", "--lib",
    ],
}


def units(command):
    env = dict(os.environ, RUSTC_BOOTSTRAP="1")
    out = subprocess.run(
        command + ["--unit-graph", "-Z", "unstable-options"],
        env=env, check=True, capture_output=True, text=True,
    ).stdout
    found = {}
    for unit in json.loads(out)["units"]:
        package = unit["pkg_id"].rsplit("#", 1)[-1]
        key = (package, unit["target"]["name"], unit["mode"], tuple(unit["target"]["kind"]))
        variant = (tuple(sorted(unit["features"])), json.dumps(unit["profile"], sort_keys=True))
        found.setdefault(key, set()).add(variant)
    return found


def main():
    (name_a, a), (name_b, b) = [(name, units(cmd)) for name, cmd in COMMANDS.items()]
    shared = sorted(set(a) & set(b))
    differing = [key for key in shared if a[key] != b[key]]
    for key in differing:
        print(f"{key[0]} ({key[1]}, {key[2]})")
        for name, graph in ((name_a, a), (name_b, b)):
            for features, profile in sorted(graph[key]):
                level = json.loads(profile)["opt_level"]
                print(f"  {name}: features {list(features)}, opt-level {level}")
    print(f"{len(shared)} crates shared by the two builds, {len(differing)} built differently")
    return 1 if differing else 0


if __name__ == "__main__":
    sys.exit(main())
