"""Bad input from Python ends in ``ProblemError`` naming the key path, never another exception:
numpy values are taken as numbers and lists, what a problem file cannot hold is refused, a long
one-line text is text, and malformed ``with_values``/``sweep`` keys are named."""
import json

import numpy as np
import pytest

import mlpg_contact as mc

BASE = {
    "name": "block",
    "geometry": {"kind": "rectangle", "x": [0.0, 2.0], "y": [-2.0, 0.0]},
    "nodes": {"spacing": 0.5},
    "material": {"young": 1.0, "poisson": 0.3, "plane": "strain"},
    "boundary": [
        {"edge": "bottom", "displacement": {"x": 0.0, "y": 0.0}},
        {"edge": "right", "traction": {"x": 0.0, "y": 0.0}},
        {"edge": "top", "traction": {"x": 0.0, "y": -0.1}},
        {"edge": "left", "traction": {"x": 0.0, "y": 0.0}},
    ],
}


def with_nodes(**nodes):
    return dict(BASE, nodes=dict(BASE["nodes"], **nodes))


def test_numpy_values_solve_like_python_numbers():
    plain = mc.solve(BASE).displacement
    as_numpy = dict(BASE, geometry={"kind": "rectangle", "x": np.array([0.0, 2.0]), "y": (-2.0, 0.0)})
    as_numpy["nodes"] = {"spacing": np.float32(0.5)}
    assert np.array_equal(mc.solve(as_numpy).displacement, plain)
    jittered = with_nodes(layout="jittered", seed=3)
    assert np.array_equal(
        mc.solve(with_nodes(layout="jittered", seed=np.int64(3))).displacement, mc.solve(jittered).displacement
    )


@pytest.mark.parametrize(
    "problem, field",
    [
        (with_nodes(spacing={0.5}), "nodes.spacing"),
        (with_nodes(spacing=0.5 + 1j), "nodes.spacing"),
        (with_nodes(spacing=np.complex128(1j)), "nodes.spacing"),
        (dict(BASE, nodes={("spacing",): 0.5}), "nodes.('spacing',)"),
    ],
    ids=["set", "complex", "numpy complex", "tuple key"],
)
def test_values_a_problem_file_cannot_hold_are_problem_errors(problem, field):
    with pytest.raises(mc.ProblemError) as e:
        mc.solve(problem)
    assert e.value.field == field


def test_deep_nesting_is_a_problem_error():
    deep = 0.5
    for _ in range(5000):
        deep = [deep]
    with pytest.raises(mc.ProblemError, match="nested deeper"):
        mc.solve(with_nodes(spacing=deep))


def test_a_long_one_line_text_is_text():
    # JSON text on one line, longer than a file name may be: parsed (as TOML, which it is
    # not), not looked up as a path.
    with pytest.raises(mc.ProblemError):
        mc.solve(json.dumps(dict(BASE, name="p" * 300)))


@pytest.mark.parametrize(
    "key", ["boundary[x].edge", "boundary[9].edge", "boundary[-1].edge", "nodes[0]", "boundary[1.edge", "a..b", ""]
)
def test_malformed_keys_are_problem_errors_naming_the_key(key):
    with pytest.raises(mc.ProblemError) as e:
        mc.with_values(BASE, {key: "top"})
    assert e.value.field == key


def test_a_sweep_grid_needs_lists():
    with pytest.raises(mc.ProblemError) as e:
        mc.sweep(BASE, {"nodes.spacing": 0.5})
    assert e.value.field == "nodes.spacing"
    with pytest.raises(mc.ProblemError):
        mc.sweep(BASE, {"boundary[7].traction.y": [0.1]})
