#!/usr/bin/env python3
"""Lamé's interference pressure of a shaft (radii a..b, a = 0 solid) in a hub (b..c), same
material, long cylinders (plane strain, ε_zz = 0), radial interference δ.

An independent check of the closed form of docs/method.md §9.9: the two Lamé problems
σ_rr = A − B/r², σ_θθ = A + B/r² are joined by the four conditions (free bore, equal radial
stress at b, free outer surface, u_hub(b) − u_shaft(b) = δ) solved as a linear system, with
u = r ε_θθ from the general Hooke's law (σ_zz = ν(σ_rr + σ_θθ)). No numpy needed.

    python3 scripts/lame_interference.py [E nu a b c delta]
"""
import sys


def solve(m, v):
    """Gaussian elimination with partial pivoting."""
    n = len(v)
    m = [row[:] + [v[i]] for i, row in enumerate(m)]
    for k in range(n):
        p = max(range(k, n), key=lambda i: abs(m[i][k]))
        m[k], m[p] = m[p], m[k]
        for i in range(k + 1, n):
            f = m[i][k] / m[k][k]
            for j in range(k, n + 1):
                m[i][j] -= f * m[k][j]
    x = [0.0] * n
    for k in reversed(range(n)):
        x[k] = (m[k][n] - sum(m[k][j] * x[j] for j in range(k + 1, n))) / m[k][k]
    return x


def hoop_strain_coeffs(e, nu, r):
    """ε_θθ(r) = cA·A + cB·B for σ_rr = A − B/r², σ_θθ = A + B/r², σ_zz = ν(σ_rr + σ_θθ)."""
    # ε_θθ = (σ_θθ − ν(σ_rr + σ_zz)) / E
    s_rr = (1.0, -1.0 / r**2)
    s_tt = (1.0, 1.0 / r**2)
    s_zz = (nu * (s_rr[0] + s_tt[0]), nu * (s_rr[1] + s_tt[1]))
    return tuple((s_tt[i] - nu * (s_rr[i] + s_zz[i])) / e for i in range(2))


def fit(e, nu, a, b, c, delta):
    """(p, u_shaft(b), u_hub(b)) for the shaft a..b in the hub b..c; unknowns As, Bs, Ah, Bh."""
    us = [b * k for k in hoop_strain_coeffs(e, nu, b)]
    uh = us[:]  # same material, same radius
    rows = [
        [1.0, -1.0 / a**2, 0.0, 0.0] if a > 0 else [0.0, 1.0, 0.0, 0.0],  # σ_rr(a) = 0 / B = 0
        [1.0, -1.0 / b**2, -1.0, 1.0 / b**2],  # σ_rr continuous at b
        [0.0, 0.0, 1.0, -1.0 / c**2],  # σ_rr(c) = 0
        [-us[0], -us[1], uh[0], uh[1]],  # u_hub(b) − u_shaft(b) = δ
    ]
    a_s, b_s, a_h, b_h = solve(rows, [0.0, 0.0, 0.0, delta])
    p = -(a_h - b_h / b**2)
    return p, us[0] * a_s + us[1] * b_s, uh[0] * a_h + uh[1] * b_h


def closed_form(e, nu, a, b, c, delta):
    """docs/method.md §9.9: p = E δ (b² − a²)(c² − b²) / (2 b³ (1 − ν²)(c² − a²))."""
    return e * delta * (b * b - a * a) * (c * c - b * b) / (2 * b**3 * (1 - nu * nu) * (c * c - a * a))


if __name__ == "__main__":
    args = [float(x) for x in sys.argv[1:]] or [210000.0, 0.3, 0.0, 10.0, 20.0, 0.01]
    p, u_s, u_h = fit(*args)
    print(f"p = {p:.10g} (closed form {closed_form(*args):.10g})")
    print(f"u_shaft(b) = {u_s:.10g}, u_hub(b) = {u_h:.10g}, difference {u_h - u_s:.10g}")
