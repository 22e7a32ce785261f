#!/usr/bin/env python3
"""Time to accuracy, side by side: the adaptive beam of mlpg-contact against the Q2 peer.

Runs ``mlpg-contact problems/beam_on_foundation_adaptive.toml`` and ``beam_q2.py --ny N``
alternately, ``--rounds`` times each, in this one process group, and prints for each the
accuracy reached (onset and total contact force against the repository's converged values)
and the minimum and median of its stage time (the sum of the per-step stage timings that
mlpg-contact prints on stderr; the peer's mesh + assembly + factorisation + condensation +
LCP + recovery, imports excluded), wall time (process start to exit) and CPU time (user +
system of the child), then the ratios peer / ours.

    python3 benches/peer/compare.py [--rounds 3] [--ny 16] [--binary target/release/mlpg-contact]
        [--python target/peer-venv/bin/python] [--problem problems/beam_on_foundation_adaptive.toml]
        [--baseline /path/to/another/mlpg-contact] [--baseline-problem <file>]

``--baseline`` also runs a second build of ours in each round (before and after a change, in
the same minutes), on ``--baseline-problem`` (default: ``--problem``; a problem file for an
older binary that does not know a newer key).

The peer runs with one BLAS thread (OPENBLAS_NUM_THREADS=1 etc.): a multi-threaded BLAS
oversubscribed on a shared 2-core machine made its condensation 20x slower, which would
flatter us. Uses only the standard library; the peer needs scikit-fem (README.md).
"""

import argparse
import json
import os
import pathlib
import re
import resource
import statistics
import subprocess
import sys
import tempfile
import time

HERE = pathlib.Path(__file__).resolve().parent
ROOT = HERE.parents[1]
REF_ONSET = 19.810
REF_FORCE = 32.3476
ONSET_TOL = 0.01
FORCE_TOL = 1e-4
STAGE = re.compile(r"^\s{2}([a-z_]+)\s+([0-9.]+) s$")


def child_cpu():
    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime


def timed(cmd, env=None):
    cpu0, t0 = child_cpu(), time.perf_counter()
    p = subprocess.run(cmd, capture_output=True, text=True, env=env, cwd=ROOT)
    wall, cpu = time.perf_counter() - t0, child_cpu() - cpu0
    if p.returncode not in (0, 3):
        sys.exit(f"{cmd[0]} failed ({p.returncode}):\n{p.stderr[-2000:]}")
    return p, wall, cpu


def ours(binary, problem):
    with tempfile.TemporaryDirectory() as out:
        p, wall, cpu = timed([binary, problem, "--out", out])
        s = json.loads((pathlib.Path(out) / "summary.json").read_text())
    stages = {}
    for line in p.stderr.splitlines():
        m = STAGE.match(line)
        if m:
            stages[m[1]] = stages.get(m[1], 0.0) + float(m[2])
    c = s["contact"]
    steps = s.get("refinement", {}).get("steps", [])
    return {
        "stage": sum(stages.values()),
        "wall": wall,
        "cpu": cpu,
        "stages": stages,
        "onset": c["onset_x"],
        "force": c["total_force"],
        "size": " -> ".join(str(k["nodes"]) for k in steps) + " nodes",
    }


def peer(python, ny, problem):
    env = dict(os.environ)
    for k in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
        env[k] = "1"
    p, wall, cpu = timed([python, str(HERE / "beam_q2.py"), "--ny", str(ny), "--problem", problem], env)
    r = json.loads(p.stdout.strip().splitlines()[-1])
    return {
        "stage": r["stage_seconds"],
        "wall": wall,
        "cpu": cpu,
        "stages": r["timings"],
        "onset": r["onset"],
        "force": r["total_force"],
        "size": f"Q2 {r['nx']} x {r['ny']} elements, {r['dofs']} DOFs",
    }


def accuracy(r):
    de, df = r["onset"] - REF_ONSET, r["force"] / REF_FORCE - 1.0
    ok = abs(de) <= ONSET_TOL and abs(df) <= FORCE_TOL
    return f"l_c {r['onset']:.4f} ({de:+.4f}), F_c {r['force']:.6f} ({df:+.1e}): {'within' if ok else 'NOT within'} the level"


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--ny", type=int, default=16, help="the peer's elements through the depth")
    ap.add_argument("--binary", default=str(ROOT / "target/release/mlpg-contact"))
    ap.add_argument("--baseline", help="a second mlpg-contact binary, run alternately too (A/B)")
    ap.add_argument("--python", default=str(ROOT / "target/peer-venv/bin/python"))
    ap.add_argument("--problem", default="problems/beam_on_foundation_adaptive.toml")
    ap.add_argument("--baseline-problem", help="the baseline's problem file (default: --problem)")
    a = ap.parse_args()
    loads = [pathlib.Path("/proc/loadavg").read_text().split()[:3]]
    runs = {"ours": [], "peer": []}
    if a.baseline:
        runs["baseline"] = []
    for k in range(a.rounds):
        if a.baseline:
            runs["baseline"].append(ours(a.baseline, a.baseline_problem or a.problem))
            b = runs["baseline"][-1]
            print(f"round {k + 1}: baseline stage {b['stage']:.2f} s wall {b['wall']:.2f} s cpu {b['cpu']:.2f} s", flush=True)
        runs["ours"].append(ours(a.binary, a.problem))
        runs["peer"].append(peer(a.python, a.ny, a.problem))
        o, q = runs["ours"][-1], runs["peer"][-1]
        print(f"round {k + 1}: ours stage {o['stage']:.2f} s wall {o['wall']:.2f} s cpu {o['cpu']:.2f} s | "
              f"peer stage {q['stage']:.2f} s wall {q['wall']:.2f} s cpu {q['cpu']:.2f} s", flush=True)
    loads.append(pathlib.Path("/proc/loadavg").read_text().split()[:3])
    print(f"\nload average at start {' '.join(loads[0])}, at end {' '.join(loads[1])}\n")
    print("| run | size | accuracy | stage s min / median | wall s min / median | CPU s min / median |")
    print("|---|---|---|---|---|---|")
    med = {}
    for name, rs in runs.items():
        row = []
        for key in ("stage", "wall", "cpu"):
            v = [r[key] for r in rs]
            med[(name, key)] = (min(v), statistics.median(v))
            row.append(f"{min(v):.2f} / {statistics.median(v):.2f}")
        print(f"| {name} | {rs[-1]['size']} | {accuracy(rs[-1])} | {' | '.join(row)} |")
    print()
    for key in ("stage", "wall", "cpu"):
        for name in [n for n in runs if n != "peer"]:
            (omin, omed), (pmin, pmed) = med[(name, key)], med[("peer", key)]
            print(f"peer / {name}, {key}: min {pmin / omin:.2f}x, median {pmed / omed:.2f}x")
    print("\nwhere the time goes (median over the rounds, s):")
    for name, rs in runs.items():
        keys = sorted(rs[0]["stages"], key=lambda k: -statistics.median(r["stages"].get(k, 0) for r in rs))
        parts = [f"{k} {statistics.median(r['stages'].get(k, 0) for r in rs):.3f}" for k in keys]
        print(f"  {name}: " + ", ".join(p for p in parts if not p.endswith(" 0.000")))


if __name__ == "__main__":
    main()
