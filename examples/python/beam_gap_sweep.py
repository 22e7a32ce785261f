"""The paper's beam on a rigid foundation from Python: one solve, then a sweep of the gap.

The cantilever of `problems/beam_on_foundation.toml` (L = 48, D = 6, clamped at x = 0, load
f = 1 per unit length on its top edge) rests, after bending, on a rigid flat foundation an
initial gap delta0 below its bottom edge (0.01 in the file). This script

1. solves the file as it is (at a coarser node spacing, `--spacing`, so that it runs in
   seconds) and prints the total contact force and the contact onset l_c;
2. sweeps the gap over eight values from 0.002 to 0.03 with `mlpg_contact.sweep` (the
   foundation is the line through `contact.obstacle_point = [0, -3 - gap]`), serially or,
   with `--dask`, on a two-worker dask `LocalCluster`;
3. plots l_c and the total contact force against the gap into a PNG (`--out`).

l_c is `summary["contact"]["onset_x"]`: the distance from the clamped end to where the beam
first touches the foundation, interpolated between the last open and the first closed
contact candidate; the error bars show that bracket (`last_open_x`, `first_closed_x`).

Needs the package (`pip install .`) and matplotlib; `--dask` also needs
`dask[distributed]`. Run it from anywhere but the `python/` folder of the repository:

    python examples/python/beam_gap_sweep.py                 # spacing 0.5, beam_gap_sweep.png
    python examples/python/beam_gap_sweep.py --spacing 0.25 --dask --out gap.png
"""
from __future__ import annotations

import argparse
import time
from pathlib import Path

import matplotlib

matplotlib.use("Agg")  # no window: the figure goes to a file
import matplotlib.pyplot as plt

import mlpg_contact as mc

ROOT = Path(__file__).resolve().parents[2]  # the repository: examples/python/ is two below
PROBLEM = ROOT / "problems" / "beam_on_foundation.toml"

# Initial gaps delta0 between the beam's bottom edge (y = -3) and the foundation; the file's
# 0.01 is among them.
GAPS = [0.002, 0.004, 0.006, 0.008, 0.01, 0.015, 0.02, 0.03]


def onset(contact: dict) -> str:
    """l_c and its bracket as text, or a note when nothing closed."""
    if contact.get("onset_x") is None:
        return "no contact"
    text = f"{contact['onset_x']:.3f} (between {contact['last_open_x']:g} and {contact['first_closed_x']:g})"
    if contact["onset_x"] != contact["onset_x_unclipped"]:
        # The extrapolation from the open candidates fell outside the bracket.
        text += f", clipped from {contact['onset_x_unclipped']:.3f}"
    return text


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--spacing", type=float, default=0.5, help="node spacing h (the file has 0.25; default 0.5)")
    parser.add_argument("--out", type=Path, default=Path("beam_gap_sweep.png"), help="the PNG to write")
    parser.add_argument("--dask", action="store_true", help="run the sweep on a 2-worker dask LocalCluster")
    args = parser.parse_args()

    # The problem file as a dict with the spacing replaced; every run below starts from it.
    base = mc.with_values(PROBLEM, {"nodes.spacing": args.spacing})

    # 1. One solve: the file's gap (0.01).
    result = mc.solve(base)
    contact = result.summary["contact"]
    print(f"beam on foundation, h = {args.spacing:g}, gap 0.01: {result.summary['counts']['nodes']} nodes")
    print(f"  total contact force F_c = {contact['total_force']:.6f}  (load f L = 48)")
    print(f"  contact onset l_c = {onset(contact)}")

    # 2. The sweep: one record per gap, {"values": {...}, "summary": {...}}, in the grid's order.
    grid = {"contact.obstacle_point": [[0.0, -3.0 - gap] for gap in GAPS]}
    start = time.perf_counter()
    if args.dask:
        from dask.distributed import Client, LocalCluster

        with LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None) as cluster:
            with Client(cluster) as client:
                rows = mc.sweep(base, grid, client=client)
    else:
        rows = mc.sweep(base, grid)
    seconds = time.perf_counter() - start
    print(f"\nsweep of {len(rows)} gaps ({'dask, 2 workers' if args.dask else 'serial'}): {seconds:.2f} s")
    print(f"  {'gap':>6}  {'F_c':>10}  l_c")
    for gap, row in zip(GAPS, rows):
        c = row["summary"]["contact"]
        print(f"  {gap:6.3f}  {c['total_force']:10.5f}  {onset(c)}")

    # 3. The plot: l_c with its bracket, and F_c, against the gap.
    closed = [(g, r["summary"]["contact"]) for g, r in zip(GAPS, rows) if r["summary"]["contact"].get("onset_x") is not None]
    gaps = [g for g, _ in closed]
    lc = [c["onset_x"] for _, c in closed]
    below = [c["onset_x"] - c["last_open_x"] for _, c in closed]
    above = [c["first_closed_x"] - c["onset_x"] for _, c in closed]
    force = [r["summary"]["contact"]["total_force"] for r in rows]

    fig, (ax_lc, ax_f) = plt.subplots(1, 2, figsize=(11, 4.5), constrained_layout=True)
    ax_lc.errorbar(gaps, lc, yerr=[below, above], fmt="o-", capsize=4, color="tab:blue",
                   label="$l_c$ (bars: last open to first closed candidate)")
    ax_lc.set_xlabel(r"initial gap $\delta_0$")
    ax_lc.set_ylabel(r"contact onset $l_c$ (distance from the clamp)")
    ax_lc.set_title("Where the beam first touches")
    ax_f.plot(GAPS, force, "s-", color="tab:red", label="$F_c$")
    ax_f.set_xlabel(r"initial gap $\delta_0$")
    ax_f.set_ylabel(r"total contact force $F_c$ (per unit thickness)")
    ax_f.set_title("Force carried by the foundation (load $fL$ = 48)")
    for ax in (ax_lc, ax_f):
        ax.axvline(0.01, color="0.6", linestyle=":", label=r"the paper's $\delta_0$ = 0.01")
        ax.grid(True, alpha=0.3)
        ax.legend(loc="best", fontsize=9)
    fig.suptitle(f"Cantilever on a rigid foundation (L = 48, D = 6, f = 1): initial gap sweep, node spacing h = {args.spacing:g}")
    fig.savefig(args.out, dpi=120)
    print(f"\nplot: {args.out}")


if __name__ == "__main__":  # needed by --dask: the cluster's worker processes import this file
    main()
