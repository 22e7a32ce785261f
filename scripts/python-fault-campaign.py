#!/usr/bin/env python3
"""The fault campaign's Python class: malformed input through the Python package.

Every leaf of two small problems (a block under a load, a block on a rigid floor) is replaced
by values of other Python and numpy types and other scales; keys are added, deleted and given
non-string types; `with_values` and `sweep` get malformed key paths and grids. Each input
ends in a result, `ProblemError` (which must name a key path: `field`), `SolveError` (a run
that fails after validation), or is a failure: any other exception, a numpy value that does
not solve like the plain Python number it stands for, an abort of the interpreter.

The inputs run in worker processes (chunks of them); a worker killed by a signal is counted
as an abort of the input it was running, and the chunk goes on in a new worker from the next
input. Deterministic in its inputs (`--seed`).

    pip install .   # the package, with numpy
    python3 scripts/python-fault-campaign.py [--seed 1] [--random 2000] [--jobs 2]

Prints a table (inputs by outcome and exception type) and exits 1 on any failure. Used by the
opt-in study `examples/studies/fault_campaign.rs` (class python); results in
docs/dev/fault_campaign.md.
"""
from __future__ import annotations

import argparse
import copy
import json
import math
import random
import subprocess
import sys
import time
from collections import Counter

BLOCK = {
    "name": "block",
    "geometry": {"kind": "rectangle", "x": [0.0, 2.0], "y": [-2.0, 0.0]},
    "nodes": {"spacing": 0.5},
    "material": {"young": 1.0, "poisson": 0.3, "plane": "strain"},
    "boundary": [
        {"edge": "bottom", "displacement": {"x": 0.0, "y": 0.0}},
        {"edge": "top", "traction": {"x": 0.0, "y": -0.1}},
    ],
}
FLOOR = {
    "name": "floor",
    "geometry": {"kind": "rectangle", "x": [0.0, 2.0], "y": [0.0, 1.0]},
    "nodes": {"spacing": 0.25},
    "material": {"young": 1000.0, "poisson": 0.3, "plane": "stress"},
    "boundary": [
        {"edge": "left", "displacement": {"x": 0.0}},
        {"edge": "top", "displacement": {"y": -0.01}},
    ],
    "contact": {"edge": "bottom", "obstacle_point": [0.0, -0.001], "obstacle_normal": [0.0, 1.0]},
}
BASES = {"block": BLOCK, "floor": FLOOR}


def leaves(v, path=()):
    if isinstance(v, dict):
        for k in v:
            yield from leaves(v[k], path + (k,))
    elif isinstance(v, list):
        for i, x in enumerate(v):
            yield from leaves(x, path + (i,))
    else:
        yield path, v


def lists(v, path=()):
    """Paths of the lists (arrays) in `v`."""
    if isinstance(v, dict):
        for k in v:
            yield from lists(v[k], path + (k,))
    elif isinstance(v, list):
        yield path, v
        for i, x in enumerate(v):
            yield from lists(x, path + (i,))


def dotted(path) -> str:
    out = ""
    for p in path:
        out += f"[{p}]" if isinstance(p, int) else (f".{p}" if out else p)
    return out


def put(v, path, x):
    if not path:
        return x
    c = dict(v) if isinstance(v, dict) else list(v)
    c[path[0]] = put(v[path[0]], path[1:], x)
    return c


def delete(v, path):
    c = dict(v) if isinstance(v, dict) else list(v)
    if len(path) == 1:
        del c[path[0]]
    else:
        c[path[0]] = delete(v[path[0]], path[1:])
    return c


class Weird:
    """An object no problem file can hold."""

    def __repr__(self):
        return "Weird()"


# Values of other types: (label, factory). Factories, so that each input gets fresh objects.
FOREIGN = [
    ("None", lambda: None),
    ("str", lambda: "x"),
    ("huge str", lambda: "9" * 1_000_000),
    ("empty list", lambda: []),
    ("empty dict", lambda: {}),
    ("True", lambda: True),
    ("2**70", lambda: 2**70),
    ("-2**63", lambda: -(2**63)),
    ("nan", lambda: float("nan")),
    ("inf", lambda: float("inf")),
    ("1e300", lambda: 1e300),
    ("5e-324", lambda: 5e-324),
    ("bytes", lambda: b"1"),
    ("bytearray", lambda: bytearray(b"1")),
    ("tuple", lambda: (1.0,)),
    ("set", lambda: {1.0}),
    ("frozenset", lambda: frozenset([1.0])),
    ("complex", lambda: 1 + 2j),
    ("object", lambda: object()),
    ("Weird", lambda: Weird()),
    ("function", lambda: (lambda: 1)),
    ("range", lambda: range(3)),
    ("dict with int key", lambda: {1: 2.0}),
    ("dict with tuple key", lambda: {("a",): 2.0}),
    ("nested list", lambda: [[[1.0]]]),
    ("deep list", lambda: deep(100)),
]


# Types no problem file can hold: refused naming the mutated key itself.
STRICT = {"bytes", "bytearray", "set", "frozenset", "complex", "object", "Weird", "function", "range", "dict with int key", "dict with tuple key"}


def deep(n):
    v = 1.0
    for _ in range(n):
        v = [v]
    return v


def numpy_values(np, v):
    """numpy stand-ins for the plain leaf `v`: (label, value, exact) where `exact` says the
    value equals `v` (it must solve like it)."""
    out = []
    if isinstance(v, bool):
        out += [("np.bool_", np.bool_(v), True)]
    elif isinstance(v, int):
        out += [("np.int64", np.int64(v), True), ("np.int32", np.int32(v), True), ("np.uint8", np.uint8(v), True)]
    elif isinstance(v, float):
        out += [
            ("np.float64", np.float64(v), True),
            ("np.float32", np.float32(v), float(np.float32(v)) == v),
            ("np.float16", np.float16(v), float(np.float16(v)) == v),
            ("0-d array", np.array(v), True),
            ("np.complex128", np.complex128(v), False),
            ("np.datetime64", np.datetime64("2020-01-01"), False),
        ]
    elif isinstance(v, str):
        out += [("np.str_", np.str_(v), True), ("np.bytes_", np.bytes_(v.encode()), False)]
    return out


def inputs(seed: int, n_random: int):
    """Every input as (kind, name, thunk) where thunk(mc, np) runs it and returns a result code
    for the worker; built lazily in the worker from the same seed, so only indices travel."""
    import numpy as np  # noqa: F401  (the worker has numpy; the parent only counts)

    cases = []
    for base_name, base in BASES.items():
        for path, v in list(leaves(base)):
            key = dotted(path)
            for label, make in FOREIGN:
                cases.append(("foreign", f"{base_name}:{key}={label}", ("put", base_name, path, make, label in STRICT)))
            if isinstance(v, float) and v != 0.0:
                for k in range(-15, 16, 3):
                    cases.append(("scale", f"{base_name}:{key}*1e{k}", ("put", base_name, path, lambda v=v, k=k: v * 10.0**k, None)))
                cases.append(("scale", f"{base_name}:{key} negated", ("put", base_name, path, lambda v=v: -v, None)))
            cases.append(("numpy", f"{base_name}:{key}=numpy", ("numpy", base_name, path, v, None)))
        for path, v in list(lists(base)):
            key = dotted(path)
            cases.append(("numpy", f"{base_name}:{key}=array", ("array", base_name, path, v, None)))
            cases.append(("foreign", f"{base_name}:{key}=tuple", ("put", base_name, path, lambda v=v: tuple(v), None)))
            cases.append(("foreign", f"{base_name}:{key}=set", ("put", base_name, path, lambda v=v: set(map(repr, v)), True)))
        for path, _ in list(leaves(base)):
            if len(path) > 1 or not isinstance(path[0], int):
                cases.append(("keys", f"{base_name}:del {dotted(path)}", ("delete", base_name, path, None, None)))
        for top in list(base):
            for label, key in [("int key", 7), ("tuple key", ("a",)), ("None key", None), ("frozenset key", frozenset("a"))]:
                cases.append(("keys", f"{base_name}:{top} {label}", ("badkey", base_name, (top,), key, None)))
            cases.append(("keys", f"{base_name}:{top}.unknown", ("extra", base_name, (top,), "unknown", None)))
    rng = random.Random(seed)
    alphabet = "abcdefghnoprstxy._[]019-"
    names = ["nodes", "spacing", "boundary", "traction", "y", "x", "material", "young", "geometry", "contact", "edge"]
    for i in range(n_random):
        r = rng.random()
        if r < 0.4:
            key = "".join(rng.choice(alphabet) for _ in range(rng.randint(0, 24)))
        elif r < 0.8:
            parts = [rng.choice(names) + (f"[{rng.choice(['0', '1', '9', '-1', 'x', '', '1.5'])}]" if rng.random() < 0.3 else "") for _ in range(rng.randint(1, 4))]
            key = rng.choice([".", ".", "..", "[", "]"]).join(parts)
        else:
            key = rng.choice([7, None, ("a",), 1.5, b"nodes", "nodes.spacing", "boundary[1].traction.y", "x" * 100_000])
        grid = rng.choice(["list", "list", "scalar", "str", "None", "set", "array", "dict", "generator", "empty"])
        cases.append(("sweep", f"sweep {key!r:.40} {grid}", ("sweep", rng.choice(list(BASES)), key, grid, i)))
    # Random combinations: two or three leaf replacements at once.
    rng = random.Random(seed + 1)
    for i in range(n_random):
        base_name = rng.choice(list(BASES))
        paths = [p for p, _ in leaves(BASES[base_name])]
        picks = [(rng.choice(paths), rng.randrange(len(FOREIGN))) for _ in range(rng.randint(2, 3))]
        cases.append(("combined", f"{base_name}:combined {i}", ("combined", base_name, picks, None, None)))
    return cases


def field_names(err, path) -> bool:
    """Whether a ProblemError names the mutated key: its `field` holds the path's last name."""
    field = getattr(err, "field", None)
    if not field:
        return False
    names = [p for p in path if isinstance(p, str)]
    return not names or names[-1] in field or field in dotted(path)


def run_case(mc, np, case, plain_cache):
    """Runs one input; returns (outcome, detail) with outcome one of ok, ProblemError,
    SolveError, unnamed (a ProblemError without the key path), mismatch, or the name of any
    other exception."""
    op, base_name, path, arg, extra = case
    base = BASES[base_name]

    def solve(problem):
        return mc.solve(problem)

    try:
        if op == "put":
            problem = put(base, path, arg())
            try:
                solve(problem)
                return "ok", ""
            except mc.ProblemError as e:
                # A value no problem file can hold must be refused naming its own key; a value
                # of a valid type may be refused through another key it contradicts.
                named = field_names(e, path) if extra else bool(e.field)
                return ("ProblemError", "") if named else ("unnamed", f"{e.field!r}: {e}")
        if op in ("numpy", "array"):
            if op == "numpy":
                variants = numpy_values(np, arg)
            else:
                variants = [("array", np.array(arg), True)]
                if all(isinstance(x, float) for x in arg):
                    variants.append(("float32 array", np.array(arg, dtype=np.float32), all(float(np.float32(x)) == x for x in arg)))
            outcomes = []
            for label, value, exact in variants:
                problem = put(base, path, value)
                try:
                    u = solve(problem).displacement
                except mc.ProblemError as e:
                    if exact:
                        # A value equal to the plain one must be taken like it when the plain one is.
                        if plain_cache.setdefault(base_name, _plain_ok(mc, base)):
                            return "mismatch", f"{label} refused: {e}"
                    outcomes.append("ProblemError" if field_names(e, path) else "unnamed")
                    continue
                if exact:
                    plain = mc.solve(put(base, path, arg)).displacement
                    if not np.array_equal(u, plain):
                        return "mismatch", f"{label}: displacement differs"
                outcomes.append("ok")
            if "unnamed" in outcomes:
                return "unnamed", ""
            return ("ok" if "ok" in outcomes else "ProblemError"), ""
        if op == "delete":
            try:
                solve(delete(base, path))
                return "ok", ""
            except mc.ProblemError:
                return "ProblemError", ""
        if op == "badkey":
            problem = copy.deepcopy(base)
            target = problem[path[0]]
            if isinstance(target, dict):
                target[arg] = 1.0
            else:
                problem[arg] = 1.0
            try:
                solve(problem)
                return "ok", ""
            except mc.ProblemError as e:
                return ("ProblemError", "") if e.field else ("unnamed", str(e))
        if op == "extra":
            problem = copy.deepcopy(base)
            target = problem[path[0]]
            if isinstance(target, dict):
                target[arg] = 1.0
            else:
                problem[path[0] + "_" + arg] = 1.0
            try:
                solve(problem)
                return "ok", ""
            except mc.ProblemError as e:
                return ("ProblemError", "") if e.field else ("unnamed", str(e))
        if op == "sweep":
            key, grid = path, arg
            values = {
                "list": [0.5],
                "scalar": 0.5,
                "str": "0.5",
                "None": None,
                "set": {0.5},
                "array": np.array([0.5]),
                "dict": {"a": 0.5},
                "generator": (x for x in [0.5]),
                "empty": [],
            }[grid]
            try:
                mc.sweep(base, {key: values})
                return "ok", ""
            except mc.ProblemError as e:
                return ("ProblemError", "") if e.field is not None else ("unnamed", str(e))
        if op == "combined":
            problem = base
            for p, k in path:
                problem = put(problem, p, FOREIGN[k][1]())
            try:
                solve(problem)
                return "ok", ""
            except mc.ProblemError as e:
                return ("ProblemError", "") if e.field else ("unnamed", str(e))
        raise AssertionError(op)
    except mc.SolveError as e:
        return "SolveError", str(e)[:200]
    except Exception as e:  # noqa: BLE001  (what the campaign looks for)
        return type(e).__name__, f"{e}"[:300]


def _plain_ok(mc, base) -> bool:
    try:
        mc.solve(base)
        return True
    except mc.ProblemError:
        return False


def worker(seed: int, n_random: int, start: int, stop: int) -> None:
    import numpy as np

    import mlpg_contact as mc

    cases = inputs(seed, n_random)
    plain_cache: dict = {}
    for i in range(start, stop):
        kind, name, case = cases[i]
        outcome, detail = run_case(mc, np, case, plain_cache)
        print(json.dumps([i, outcome, detail]), flush=True)


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--random", type=int, default=2000, help="random sweep keys, and as many random combinations")
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--chunk", type=int, default=500)
    ap.add_argument("--show-solve-errors", action="store_true", help="list the inputs that ended in SolveError, with the message")
    ap.add_argument("--worker", nargs=2, type=int, help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.worker:
        worker(args.seed, args.random, *args.worker)
        return 0
    start = time.time()
    cases = inputs(args.seed, args.random)
    n = len(cases)
    results: dict[int, tuple[str, str]] = {}
    pending = [(a, min(a + args.chunk, n)) for a in range(0, n, args.chunk)]
    running: list = []

    def spawn(a, b):
        cmd = [sys.executable, __file__, "--seed", str(args.seed), "--random", str(args.random), "--worker", str(a), str(b)]
        return (a, b, subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True))

    while pending or running:
        while pending and len(running) < args.jobs:
            running.append(spawn(*pending.pop(0)))
        a, b, p = running.pop(0)
        out, err = p.communicate()
        done = [json.loads(line) for line in out.splitlines() if line.startswith("[")]
        for i, outcome, detail in done:
            results[i] = (outcome, detail)
        last = done[-1][0] if done else a - 1
        if p.returncode != 0 and last + 1 < b:
            # The input in flight ended the worker: an abort; go on from the next one.
            results[last + 1] = ("abort", f"exit {p.returncode}: {err.strip()[-300:]}")
            if last + 2 < b:
                pending.insert(0, (last + 2, b))
    elapsed = time.time() - start
    table: dict[str, Counter] = {}
    for i, (kind, name, _) in enumerate(cases):
        table.setdefault(kind, Counter())[results[i][0]] += 1
    columns = ["ok", "ProblemError", "SolveError", "unnamed", "mismatch", "abort"]
    others = sorted({o for c in table.values() for o in c} - set(columns))
    columns += others
    print(f"python fault campaign, seed {args.seed}: {n} inputs in {elapsed:.0f} s\n")
    print("| class | inputs | " + " | ".join(columns) + " |")
    print("|---|---:|" + "---:|" * len(columns))
    total = Counter()
    for kind, c in table.items():
        total.update(c)
        print(f"| {kind} | {sum(c.values())} | " + " | ".join(str(c.get(k, 0)) for k in columns) + " |")
    print(f"| all | {n} | " + " | ".join(str(total.get(k, 0)) for k in columns) + " |")
    bad = [(i, r) for i, r in results.items() if r[0] not in ("ok", "ProblemError", "SolveError")]
    print(f"\n{len(bad)} failures")
    for i, (outcome, detail) in bad[:40]:
        print(f"- {cases[i][1]}: {outcome}: {detail}")
    if args.show_solve_errors:
        solve_errors = [(i, r) for i, r in sorted(results.items()) if r[0] == "SolveError"]
        print(f"\n{len(solve_errors)} SolveError outcomes")
        for i, (_, detail) in solve_errors:
            print(f"- {cases[i][1]}: {detail}")
    # The last line, for the study: inputs, ok, refused (ProblemError), SolveError, failures.
    print(f"\nSUMMARY {n} {total['ok']} {total['ProblemError']} {total['SolveError']} {len(bad)}")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
