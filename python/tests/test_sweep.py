"""A sweep on a dask.distributed LocalCluster equals the same sweep run serially."""
from pathlib import Path

import pytest

import mlpg_contact as mc

ROOT = Path(__file__).resolve().parents[2]


def test_dask_sweep_equals_serial():
    distributed = pytest.importorskip("dask.distributed")
    base = ROOT / "problems" / "beam_on_foundation.toml"
    grid = {"nodes.spacing": [1.0, 0.5], "contact.obstacle_point": [[0.0, -3.01], [0.0, -3.02]]}
    serial = mc.sweep(base, grid)
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None) as cluster:
        with distributed.Client(cluster) as client:
            parallel = mc.sweep(base, grid, client=client)
    assert len(serial) == 4
    strip = lambda rows: [
        {"values": r["values"], "contact": r["summary"]["contact"], "counts": r["summary"]["counts"]}
        for r in rows
    ]
    assert strip(parallel) == strip(serial)
    # The gap matters: a larger gap closes fewer candidates.
    forces = {(r["values"]["nodes.spacing"], r["values"]["contact.obstacle_point"][1]): r["summary"]["contact"]["total_force"] for r in serial}
    assert forces[(0.5, -3.02)] < forces[(0.5, -3.01)]
