#!/usr/bin/env python3
"""The finite element peer of the adaptive beam: scikit-fem Q2 elements and an exact LCP.

The paper's beam on a rigid foundation (geometry, material, load and gap read from
``problems/beam_on_foundation_adaptive.toml``) on a uniform mesh of square 9-node Lagrange
(Q2) elements, ``ny`` through the depth and ``8 ny`` along the length. Contact: every
bottom-edge node (vertices and mid-side nodes, the clamped corner excluded) is a candidate;
its normal force ``r_i >= 0`` acts on the node's normal displacement, its gap is
``g_i = g0_i + n . u_i >= 0``, ``r_i g_i = 0``. The stiffness is factorised once (SuperLU),
the contact is condensed onto the candidates, ``M = E^T K^-1 E``, ``q = g0 + E^T K^-1 f``,
and the LCP ``w = q + M r`` is solved exactly by Lemke's algorithm (complementary pivoting
on the dense tableau); the displacement follows from ``K u = f + E r``.

Reported like ``mlpg-contact``'s summary: the total contact force, the onset ``l_c`` (the
same estimator as ``contact::onset``: ``gap^(2/3)`` extrapolated from the last two open
candidates, clipped to [last open, first closed]) and the stage times.

    python beam_q2.py --ny 16            # one timed solve, one JSON line on stdout
    python beam_q2.py --search           # the ladder of meshes against the level

The level: ``|l_c - 19.810| <= 0.01`` and ``|F_c / 32.3476 - 1| <= 1e-4`` (the repository's
converged values, docs/dev/time_to_accuracy.md). Optional tooling: nothing in ``cargo test``
depends on it.
"""

import argparse
import json
import pathlib
import sys
import time
import tomllib

import numpy as np
import scipy.sparse.linalg as spla
from skfem import (
    Basis,
    BilinearForm,
    ElementQuad2,
    ElementVector,
    FacetBasis,
    LinearForm,
    MeshQuad,
    asm,
)
from skfem.helpers import ddot, sym_grad, trace, eye

ROOT = pathlib.Path(__file__).resolve().parents[2]
PROBLEM = ROOT / "problems" / "beam_on_foundation_adaptive.toml"
REF_ONSET = 19.810
REF_FORCE = 32.3476
ONSET_TOL = 0.01
FORCE_TOL = 1e-4


def read_problem(path):
    with open(path, "rb") as f:
        p = tomllib.load(f)
    g, m, c = p["geometry"], p["material"], p["contact"]
    assert g["kind"] == "rectangle" and m["plane"] == "stress"
    assert c["edge"] == "bottom" and c["obstacle_normal"] == [0.0, 1.0]
    (left,) = [b for b in p["boundary"] if b["edge"] == "left"]
    (top,) = [b for b in p["boundary"] if b["edge"] == "top"]
    assert left["displacement"] == {"x": 0.0, "y": 0.0}
    return {
        "x": g["x"],
        "y": g["y"],
        "E": m["young"],
        "nu": m["poisson"],
        "traction_y": top["traction"]["y"],
        "obstacle_y": c["obstacle_point"][1],
    }


def lemke(M, q, max_pivots=None):
    """Solves w = q + M z, w, z >= 0, w.z = 0 by Lemke's algorithm (covering vector 1).

    Returns (z, pivots). Raises on ray termination (impossible for a P-matrix M)."""
    n = len(q)
    if (q >= 0).all():
        return np.zeros(n), 0
    # Tableau rows: w - M z - z0 1 = q. Columns: w (0..n-1), z (n..2n-1), z0 (2n), rhs.
    T = np.hstack([np.eye(n), -M, -np.ones((n, 1)), q[:, None]]).astype(float)
    basis = np.arange(n)
    z0 = 2 * n

    def pivot(r, col):
        T[r] /= T[r, col]
        f = T[:, col].copy()
        f[r] = 0.0
        T[:] -= np.outer(f, T[r])

    r = int(np.argmin(q))
    pivot(r, z0)
    leaving, basis[r] = basis[r], z0
    pivots = 1
    limit = max_pivots or 50 * n
    while pivots < limit:
        entering = leaving + n if leaving < n else leaving - n
        col = T[:, entering]
        ok = col > 1e-12 * max(1.0, np.abs(col).max())
        if not ok.any():
            raise RuntimeError("Lemke: ray termination")
        ratios = np.full(n, np.inf)
        ratios[ok] = T[ok, -1] / col[ok]
        best = ratios.min()
        ties = np.flatnonzero(ratios <= best + 1e-12 * max(1.0, abs(best)))
        r = next((t for t in ties if basis[t] == z0), ties[0])
        pivot(r, entering)
        leaving, basis[r] = basis[r], entering
        pivots += 1
        if leaving == z0:
            z = np.zeros(n)
            for i, b in enumerate(basis):
                if n <= b < 2 * n:
                    z[b - n] = T[i, -1]
            return np.maximum(z, 0.0), pivots
    raise RuntimeError("Lemke: pivot limit")


def onset(arc, gap, pressure, closed):
    """contact::onset of mlpg-contact, the gap side: (l_c, last_open, first_closed, zones)."""
    zones = int(sum(1 for c in range(len(arc)) if closed[c] and (c == 0 or not closed[c - 1])))
    first = int(np.argmax(closed)) if closed.any() else None
    if first is None or first == 0:
        return float("nan"), float("nan"), float("nan"), zones
    lo, hi = arc[first - 1], arc[first]
    lc = float("nan")
    if first >= 2:
        x1, x2 = arc[first - 2], arc[first - 1]
        y1, y2 = max(gap[first - 2], 0.0) ** (2 / 3), max(gap[first - 1], 0.0) ** (2 / 3)
        if y1 != y2:
            lc = min(max(x2 - y2 * (x2 - x1) / (y2 - y1), lo), hi)
    return lc, float(lo), float(hi), zones


def solve(prob, ny):
    """One Q2 solve with ny elements through the depth; returns the result dict."""
    t = {}
    t0 = time.perf_counter()
    (x0, x1), (y0, y1) = prob["x"], prob["y"]
    nx = int(round(ny * (x1 - x0) / (y1 - y0)))
    mesh = MeshQuad.init_tensor(np.linspace(x0, x1, nx + 1), np.linspace(y0, y1, ny + 1))
    elem = ElementVector(ElementQuad2())
    basis = Basis(mesh, elem, intorder=4)
    top = FacetBasis(mesh, elem, facets=mesh.facets_satisfying(lambda x: np.isclose(x[1], y1)))
    E, nu = prob["E"], prob["nu"]
    mu = E / (2 * (1 + nu))
    lam = E * nu / (1 - nu**2)  # plane stress

    @BilinearForm
    def stiffness(u, v, w):
        eu = sym_grad(u)
        return ddot(2 * mu * eu + lam * eye(trace(eu), 2), sym_grad(v))

    ty = prob["traction_y"]

    @LinearForm
    def traction(v, w):
        return ty * v.value[1]

    t["mesh"] = time.perf_counter() - t0
    t0 = time.perf_counter()
    K = asm(stiffness, basis).tocsc()
    f = asm(traction, top)
    t["assembly"] = time.perf_counter() - t0

    t0 = time.perf_counter()
    clamped = basis.get_dofs(lambda x: np.isclose(x[0], x0)).all()
    bottom = basis.get_dofs(lambda x: np.isclose(x[1], y0)).all("u^2")
    arc = basis.doflocs[0, bottom]
    keep = ~np.isclose(arc, x0)
    bottom, arc = bottom[keep], arc[keep]
    order = np.argsort(arc)
    bottom, arc = bottom[order], arc[order]
    free = np.setdiff1d(np.arange(basis.N), clamped)
    index = np.full(basis.N, -1)
    index[free] = np.arange(len(free))
    Kf = K[free][:, free].tocsc()
    lu = spla.splu(Kf, permc_spec="COLAMD")
    t["factorisation"] = time.perf_counter() - t0

    t0 = time.perf_counter()
    m = len(bottom)
    Ecols = np.zeros((len(free), m + 1), order="F")
    Ecols[index[bottom], np.arange(m)] = 1.0  # unit upward force (normal (0, 1)) on each
    Ecols[:, m] = f[free]
    X = lu.solve(Ecols)
    M = X[index[bottom], :m]
    M = 0.5 * (M + M.T)
    g0 = y0 - prob["obstacle_y"]
    q = g0 + X[index[bottom], m]
    t["condensation"] = time.perf_counter() - t0

    t0 = time.perf_counter()
    r, pivots = lemke(M, q)
    w = q + M @ r
    t["lcp"] = time.perf_counter() - t0

    t0 = time.perf_counter()
    u = np.zeros(basis.N)
    u[free] = X[:, m] + X[:, :m] @ r
    t["recovery"] = time.perf_counter() - t0

    scale = max(np.abs(r).max(), 1e-300)
    closed = r > 1e-10 * scale
    lc, lo, hi, zones = onset(arc, w, r, closed)
    force = float(r.sum())
    return {
        "ny": ny,
        "nx": nx,
        "elements": nx * ny,
        "dofs": int(len(free)),
        "candidates": int(m),
        "closed": int(closed.sum()),
        "zones": zones,
        "pivots": pivots,
        "complementarity": float(np.abs(r * w).max()),
        "min_gap": float(w.min()),
        "total_force": force,
        "onset": lc,
        "bracket": [lo, hi],
        "onset_error": lc - REF_ONSET,
        "force_rel_error": force / REF_FORCE - 1.0,
        "within": bool(abs(lc - REF_ONSET) <= ONSET_TOL and abs(force / REF_FORCE - 1) <= FORCE_TOL),
        "tip_uy": float(u[basis.get_dofs(lambda x: np.isclose(x[0], x1)).all("u^2")].mean()),
        "timings": t,
        "stage_seconds": float(sum(t.values())),
    }


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--ny", type=int, default=16, help="elements through the depth")
    ap.add_argument("--search", action="store_true", help="the ladder of meshes")
    ap.add_argument("--problem", default=str(PROBLEM))
    a = ap.parse_args()
    prob = read_problem(a.problem)
    if not a.search:
        t0 = time.perf_counter()
        res = solve(prob, a.ny)
        res["wall_in_process"] = time.perf_counter() - t0
        print(json.dumps(res))
        return 0
    print("| ny | elements | DOFs | candidates | F_c | F_c/ref-1 | l_c | l_c-ref | bracket | zones | within | stage s |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|")
    cheapest = None
    for ny in (4, 6, 8, 10, 12, 14, 16, 20, 24, 32):
        r = solve(prob, ny)
        print(
            f"| {ny} | {r['elements']} | {r['dofs']} | {r['candidates']} | {r['total_force']:.6f} "
            f"| {r['force_rel_error']:+.1e} | {r['onset']:.4f} | {r['onset_error']:+.4f} "
            f"| [{r['bracket'][0]:.5g}, {r['bracket'][1]:.5g}] | {r['zones']} | {r['within']} "
            f"| {r['stage_seconds']:.2f} |",
            flush=True,
        )
        if r["within"] and cheapest is None:
            cheapest = ny
    print(f"\ncheapest uniform mesh within the level: ny = {cheapest}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
