"""mlpg-contact from Python: solve 2-D elastostatic contact problems (meshless mixed MLPG finite
volume method, or the built-in finite elements) and get numpy arrays back.

    import mlpg_contact as mc
    result = mc.solve("problems/beam_on_foundation.toml")
    print(result.summary["contact"]["total_force"])
    u = result.displacement          # n x 2 numpy array
    result.write("out/beam")         # the command line's output files

A problem is a path to a problem file, the text of one, or a dict with the same keys
(`{"geometry": {"kind": "rectangle", ...}, ...}`); the keys are documented in the user guide
(docs/guide/src/reference/).
"""
from __future__ import annotations

import copy
import json
import os
from pathlib import Path
from typing import Any, Iterable, Mapping, Union

from . import _native
from ._native import ProblemError, SolveError

__version__: str = _native.__version__
"""The package's version (the extension's, which is the project's)."""

__all__ = ["solve", "sweep", "with_values", "Result", "ProblemError", "SolveError", "__version__"]

Problem = Union[str, "os.PathLike[str]", Mapping[str, Any]]


class Result:
    """A solved problem: arrays of the (first) body, the contact table, the summary."""

    def __init__(self, native: Any):
        self._native = native
        self._summary = None

    @property
    def summary(self) -> dict:
        """The contents of ``summary.json`` as a dict."""
        if self._summary is None:
            self._summary = json.loads(self._native.summary_json())
        return self._summary

    @property
    def nodes(self):
        """Node coordinates, ``n x 2``."""
        return self._native.nodes()

    @property
    def displacement(self):
        """Displacement ``u^h`` at the nodes, ``n x 2``."""
        return self._native.displacement()

    @property
    def stress(self):
        """Stress ``(s_xx, s_yy, s_xy)`` at the nodes, ``n x 3``."""
        return self._native.stress()

    @property
    def reactions(self) -> dict:
        """Reactions: arrays ``node``, ``axis`` (0 = x, 1 = y) and ``force``."""
        return self._native.reactions()

    @property
    def contact(self) -> dict | None:
        """The columns of ``contact.csv`` as arrays, or ``None`` without contact."""
        return self._native.contact()

    def second_body(self) -> dict:
        """Arrays of the second body of a two-body contact: ``nodes``, ``displacement``,
        ``stress``, ``reactions``."""
        n = self._native
        return {
            "nodes": n.nodes(second=True),
            "displacement": n.displacement(second=True),
            "stress": n.stress(second=True),
            "reactions": n.reactions(second=True),
        }

    def write(self, out: Union[str, "os.PathLike[str]"], report: bool = False) -> list[Path]:
        """Writes the command line's output files into ``out`` (the earlier run's files
        replaced, any other file kept, as by the command line); with
        ``report=True`` also ``report.html``."""
        return [Path(p) for p in self._native.write(os.fspath(out), report)]

    def report(self, out: Union[str, "os.PathLike[str]"]) -> Path:
        """Writes the output files and ``report.html`` (one self-contained page: the problem,
        the results, the plots inline) into ``out``; returns the page's path."""
        written = self.write(out, report=True)
        return next(p for p in written if p.name == "report.html")


def _problem_error(field: str, value: Any, reason: str) -> ProblemError:
    """A ``ProblemError`` raised on the Python side, with the attributes the extension sets."""
    err = ProblemError(f"`{field}` = {value!r}: {reason}")
    err.field, err.value, err.reason = field, repr(value), reason
    return err


# Deeper than any problem file nests (tables in arrays in tables: four or five levels).
_MAX_DEPTH = 32


def _plain(value: Any, field: str, depth: int = 0) -> Any:
    """``value`` as plain JSON data: numpy scalars and arrays become numbers and lists, tuples
    lists; anything a problem file cannot hold raises ``ProblemError`` naming the key path."""
    if depth > _MAX_DEPTH:
        raise _problem_error(field, "...", f"nested deeper than {_MAX_DEPTH} levels")
    if isinstance(value, Mapping):
        out = {}
        for key, item in value.items():
            if not isinstance(key, str):
                raise _problem_error(f"{field}.{key!r}" if field else repr(key), key, "keys are strings")
            out[key] = _plain(item, f"{field}.{key}" if field else key, depth + 1)
        return out
    if isinstance(value, (list, tuple)):
        return [_plain(item, f"{field}[{i}]", depth + 1) for i, item in enumerate(value)]
    if value is None or isinstance(value, (bool, int, float, str)):
        return value
    tolist = getattr(value, "tolist", None)  # numpy scalars and arrays
    if callable(tolist) and type(value).__module__ == "numpy":
        converted = tolist()
        if isinstance(converted, (list, bool, int, float)):
            return _plain(converted, field, depth + 1)
    raise _problem_error(
        field, value, f"a {type(value).__name__} is not a problem-file value (numbers, strings, booleans, lists, tables)"
    )


def _path(problem: Problem) -> Path | None:
    """The problem file's path, if ``problem`` names one."""
    if isinstance(problem, os.PathLike):
        return Path(problem)
    if isinstance(problem, str) and "\n" not in problem:
        # One line naming a file (or ending in .toml) is a path; anything else is TOML text
        # (a line too long to name a file, e.g. JSON text, included).
        if problem.endswith(".toml"):
            return Path(problem)
        try:
            if Path(problem).is_file():
                return Path(problem)
        except (OSError, ValueError):
            return None
    return None


def _text(problem: Problem) -> tuple[str, str, str | None]:
    """(text, format, folder) of a problem given as a path, TOML text or a dict; ``folder`` is
    the problem file's folder (relative mesh paths are taken from there), else ``None``."""
    if isinstance(problem, Mapping):
        return json.dumps(_plain(problem, "")), "json", None
    path = _path(problem)
    if path is not None:
        return path.read_text(encoding="utf-8"), "toml", str(path.resolve().parent)
    if isinstance(problem, str):
        return problem, "toml", None
    raise TypeError(f"a problem is a path, TOML text or a dict, not {type(problem).__name__}")


def solve(problem: Problem) -> Result:
    """Solves a problem (a path to a problem file, its text, or a dict of the same keys).

    A dict may hold numpy scalars and arrays (taken as numbers and lists) and tuples (lists).
    Raises ``ProblemError`` (a ``ValueError`` with ``field``, ``value`` and ``reason``) for
    invalid input, a value no problem file can hold (a set, a complex number) included, and ``SolveError`` (a ``RuntimeError`` with ``keys``) when the run fails.
    The GIL is released while solving, so threads can solve in parallel.
    """
    text, fmt, folder = _text(problem)
    return Result(_native.solve(text, fmt, folder))


def _as_dict(problem: Problem) -> dict:
    if isinstance(problem, Mapping):
        return copy.deepcopy(dict(problem))
    import tomllib

    text, _, folder = _text(problem)
    out = tomllib.loads(text)
    if folder is not None:
        # A dict has no folder: a relative mesh path becomes the file's own, absolute.
        for geometry in [out.get("geometry")] + [b.get("geometry") for b in out.get("body", [])]:
            if isinstance(geometry, dict) and "file" in geometry and not Path(geometry["file"]).is_absolute():
                geometry["file"] = str(Path(folder) / geometry["file"])
    return out


def with_values(problem: Problem, values: Mapping[str, Any]) -> dict:
    """A copy of ``problem`` as a dict with dotted keys set, e.g.
    ``{"nodes.spacing": 0.5, "contact.obstacle_point": [0, -3.02]}``; a list index is
    written ``boundary[1].traction.y``. A key path that does not fit the problem (an index out
    of range or not a number, a table used as a list) raises ``ProblemError`` naming it."""
    out = _as_dict(problem)
    for key, value in values.items():
        try:
            _set(out, key, value)
        except (KeyError, IndexError, TypeError, ValueError, AttributeError) as e:
            raise _problem_error(
                key if isinstance(key, str) else repr(key), value, f"no such key path ({type(e).__name__}: {e}); write tables with dots and "
                "list entries with an index in brackets, e.g. `boundary[1].traction.y`"
            ) from None
    return out


def _set(out: dict, key: str, value: Any) -> None:
    """Sets the dotted ``key`` of :func:`with_values` in ``out``."""
    if not isinstance(key, str) or not key:
        raise ValueError("a key path is a non-empty string")
    node: Any = out
    parts = key.split(".")
    for k, part in enumerate(parts):
        name, bracket, index = part.partition("[")
        last = k == len(parts) - 1
        if not name:
            raise ValueError(f"empty name in {part!r}")
        if bracket:
            if not index.endswith("]"):
                raise ValueError(f"unclosed index in {part!r}")
            i = int(index[:-1])
            if i < 0:
                raise IndexError(f"negative index {i}")
            node = node[name]
            if not isinstance(node, list):
                raise TypeError(f"{name!r} is not a list")
            if last:
                node[i] = value
            else:
                node = node[i]
        elif last:
            node[name] = value
        else:
            node = node.setdefault(name, {})
            if not isinstance(node, dict):
                raise TypeError(f"{name!r} is not a table")


def _summary_row(problem: dict) -> dict:
    return solve(problem).summary


def sweep(base: Problem, grid: Mapping[str, Iterable[Any]], client: Any = None) -> list[dict]:
    """Solves ``base`` for every combination of the values in ``grid`` (dotted keys as in
    :func:`with_values`) and returns one record per run: the swept values and the summary.

    With a ``dask.distributed`` ``client`` the runs go to its workers (``client.map``), on a
    ``LocalCluster`` or on a cluster of many machines alike; without one they run here, one
    after the other. The records come back in the order of the grid either way.
    """
    import itertools

    keys = list(grid)
    for k in keys:
        if isinstance(grid[k], (str, bytes)) or not isinstance(grid[k], Iterable):
            raise _problem_error(k if isinstance(k, str) else repr(k), grid[k], "a sweep's grid gives a list of values for each key")
    combos = [dict(zip(keys, values)) for values in itertools.product(*(list(grid[k]) for k in keys))]
    problems = [with_values(base, c) for c in combos]
    if client is None:
        summaries = [_summary_row(p) for p in problems]
    else:
        futures = client.map(_summary_row, problems, pure=False)
        summaries = client.gather(futures)
    return [{"values": c, "summary": s} for c, s in zip(combos, summaries)]
