"""Benchmark: a sweep of beam runs on a 2-worker dask LocalCluster against the same runs here.

The runs are the paper's beam (`problems/beam_on_foundation.toml`) at node spacing `--spacing`
(default 0.2: 7 471 nodes, about 0.25 s a run on a 2-core machine) for `--runs`
initial gaps (default 40: 0.001, 0.002, ..., 0.040). The script

1. runs the sweep serially in this process (`mlpg_contact.sweep(base, grid)`);
2. starts a `LocalCluster` (`--workers` processes, default 2, one thread each), runs the
   same sweep on it (`mlpg_contact.sweep(base, grid, client=client)`) and closes it;
3. prints a table: runs, serial seconds, dask seconds with and without the cluster's
   start-up, the speed-ups, and checks that both sweeps give identical summaries apart from
   their wall-clock `timings`.

It also prints the solver's own stage times (`timings`) summed over each sweep's runs: when
they are much larger on the workers than serially, the workers waited for a core. On a shared
machine the other processes' load decides the speed-up, so on Linux the script prints how
many cores the whole machine kept busy (from /proc/stat) in the two seconds before it starts
and during each sweep: two workers on two cores can only gain fully when both are free.

A solve can itself use up to two cores: the sparse LU's numeric factorisation runs as two
rayon tasks. The script prints the serial sweep's CPU time over its wall time; with
`RAYON_NUM_THREADS=1` in the environment (inherited by the workers) each solve uses one core.

    python examples/python/sweep_benchmark.py                      # 40 runs at h = 0.2
    python examples/python/sweep_benchmark.py --runs 20 --spacing 0.25

Needs the package (`pip install .`) and `dask[distributed]`. Run it from anywhere but
the `python/` folder of the repository.
"""
from __future__ import annotations

import argparse
import os
import time
from pathlib import Path

import mlpg_contact as mc

ROOT = Path(__file__).resolve().parents[2]  # the repository: examples/python/ is two below
PROBLEM = ROOT / "problems" / "beam_on_foundation.toml"


def without_timings(value):
    """A summary without its wall-clock `timings` (which differ between any two runs)."""
    if isinstance(value, dict):
        return {k: without_timings(v) for k, v in value.items() if k != "timings"}
    if isinstance(value, list):
        return [without_timings(v) for v in value]
    return value


def cpu_jiffies() -> tuple[int, int] | None:
    """(busy, total) clock ticks of the whole machine so far, from /proc/stat (Linux only):
    how busy the cores were, this script's processes and everyone else's."""
    try:
        with open("/proc/stat") as f:
            ticks = [int(t) for t in f.readline().split()[1:]]
    except (OSError, ValueError):
        return None
    idle = ticks[3] + ticks[4]  # idle, iowait
    return sum(ticks) - idle, sum(ticks)


def busy_cores(before, after) -> str:
    """Cores busy on average between two `cpu_jiffies()` readings, as text."""
    if before is None or after is None or after[1] == before[1]:
        return "unknown"
    share = (after[0] - before[0]) / (after[1] - before[1])
    return f"{share * (os.cpu_count() or 1):.2f} of {os.cpu_count()}"


def solver_seconds(rows) -> float:
    """The solver's own time summed over a sweep's runs (the stage times in `timings`)."""
    return sum(sum(r["summary"]["timings"].values()) for r in rows)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--runs", type=int, default=40, help="number of gaps (runs), default 40")
    parser.add_argument("--spacing", type=float, default=0.2, help="node spacing h, default 0.2")
    parser.add_argument("--workers", type=int, default=2, help="worker processes of the LocalCluster, default 2")
    args = parser.parse_args()

    from dask.distributed import Client, LocalCluster

    base = mc.with_values(PROBLEM, {"nodes.spacing": args.spacing})
    gaps = [round(0.001 * (k + 1), 6) for k in range(args.runs)]
    grid = {"contact.obstacle_point": [[0.0, -3.0 - gap] for gap in gaps]}

    # 1. Serial, in this process.
    idle_before = cpu_jiffies()
    time.sleep(2.0)  # the machine's load before we add ours
    idle_load = busy_cores(idle_before, cpu_jiffies())
    machine = cpu_jiffies()
    wall, cpu = time.perf_counter(), time.process_time()
    serial = mc.sweep(base, grid)
    serial_s, serial_cpu = time.perf_counter() - wall, time.process_time() - cpu
    serial_load = busy_cores(machine, cpu_jiffies())
    nodes = serial[0]["summary"]["counts"]["nodes"]

    # 2. The same runs on a LocalCluster: start-up (processes, connection) timed apart.
    machine = cpu_jiffies()
    start = time.perf_counter()
    with LocalCluster(
        n_workers=args.workers, threads_per_worker=1, processes=True, dashboard_address=None
    ) as cluster, Client(cluster) as client:
        client.wait_for_workers(args.workers)
        ready = time.perf_counter()
        parallel = mc.sweep(base, grid, client=client)
        done = time.perf_counter()
    dask_load = busy_cores(machine, cpu_jiffies())
    dask_total, dask_runs = done - start, done - ready

    # 3. The table and the check.
    same = [without_timings(r["summary"]) for r in serial] == [without_timings(r["summary"]) for r in parallel]
    same = same and [r["values"] for r in serial] == [r["values"] for r in parallel]
    print(
        f"beam on foundation, h = {args.spacing:g} ({nodes} nodes), {args.runs} gaps "
        f"{gaps[0]:g} ... {gaps[-1]:g}; {os.cpu_count()} cores, "
        f"RAYON_NUM_THREADS={os.environ.get('RAYON_NUM_THREADS', 'unset')}"
    )
    print(f"serial: {serial_s / args.runs:.3f} s a run, CPU time / wall time = {serial_cpu / serial_s:.2f}")
    print(
        f"solver's stage times summed over the runs: {solver_seconds(serial):.2f} s serial, "
        f"{solver_seconds(parallel):.2f} s on the workers"
    )
    print(
        f"machine's busy cores (all processes, /proc/stat): {idle_load} in the 2 s before, "
        f"{serial_load} during the serial sweep, {dask_load} during the dask sweep"
    )
    print()
    print(f"| runs | serial (s) | dask, {args.workers} workers, incl. start-up (s) | excl. start-up (s) | speed-up incl. | speed-up excl. |")
    print("|---:|---:|---:|---:|---:|---:|")
    print(
        f"| {args.runs} | {serial_s:.2f} | {dask_total:.2f} | {dask_runs:.2f} | "
        f"{serial_s / dask_total:.2f} | {serial_s / dask_runs:.2f} |"
    )
    print()
    print(f"summaries identical apart from timings: {'yes' if same else 'NO'}")
    if not same:
        raise SystemExit(1)


if __name__ == "__main__":  # needed: the cluster's worker processes import this file
    main()
