"""The Python front end against the command line: same files, same numbers, named errors."""
import json
import os
import subprocess
import tomllib
from pathlib import Path

import numpy as np
import pytest

import mlpg_contact as mc

ROOT = Path(__file__).resolve().parents[2]
ALL_PROBLEMS = sorted((ROOT / "problems").glob("*.toml"))
# Elastodynamics ([dynamics]) runs on the command line only for now.
DYNAMIC = [p for p in ALL_PROBLEMS if "\n[dynamics]\n" in p.read_text()]
PROBLEMS = [p for p in ALL_PROBLEMS if p not in DYNAMIC]


def cli_binary() -> Path:
    """The command line built by `cargo build --release` (or `cargo test --release`)."""
    path = Path(os.environ.get("MLPG_CONTACT_BIN", ROOT / "target" / "release" / "mlpg-contact"))
    if not path.exists():
        pytest.fail(f"{path} not found: run `cargo build --release` first or set MLPG_CONTACT_BIN")
    return path


def without_timings(summary: dict) -> dict:
    """summary.json without its wall-clock timings (which differ between any two runs)."""
    def strip(v):
        if isinstance(v, dict):
            return {k: strip(x) for k, x in v.items() if k != "timings"}
        if isinstance(v, list):
            return [strip(x) for x in v]
        return v

    return strip(summary)


@pytest.mark.parametrize("path", PROBLEMS, ids=[p.stem for p in PROBLEMS])
def test_outputs_equal_the_command_line(path, tmp_path):
    result = mc.solve(path)
    written = result.write(tmp_path / "py")
    subprocess.run([cli_binary(), path, "--out", tmp_path / "cli", "--quiet"], check=True)
    cli_files = sorted(
        p.relative_to(tmp_path / "cli")
        for p in (tmp_path / "cli").rglob("*")
        if p.is_file() and p.name != ".mlpg-contact-manifest"  # the list of the files, not an output
    )
    py_files = sorted(p.relative_to(tmp_path / "py") for p in written)
    assert py_files == cli_files
    for rel in cli_files:
        a, b = (tmp_path / "py" / rel), (tmp_path / "cli" / rel)
        if rel.name == "summary.json":
            assert without_timings(json.loads(a.read_text())) == without_timings(json.loads(b.read_text()))
        else:
            assert a.read_bytes() == b.read_bytes(), rel
    # The arrays are the numbers behind the CSV files (written with 12 significant digits).
    table = np.loadtxt(tmp_path / "cli" / "displacement.csv", delimiter=",", skiprows=1)
    assert np.allclose(result.nodes, table[:, 1:3], rtol=1e-11, atol=0)
    scale = np.abs(result.displacement).max()
    assert np.abs(result.displacement - table[:, 3:5]).max() <= 1e-11 * scale
    assert result.summary == json.loads(json.dumps(result.summary))
    if result.contact is not None:
        c = np.genfromtxt(tmp_path / "cli" / "contact.csv", delimiter=",", names=True)
        force = result.contact["force"]
        assert np.abs(force - c["force"]).max() <= 1e-11 * max(np.abs(force).max(), 1e-300)
        assert np.array_equal(result.contact["in_contact"], c["in_contact"].astype(bool))


@pytest.mark.parametrize("path", DYNAMIC, ids=[p.stem for p in DYNAMIC])
def test_a_dynamic_problem_is_refused_naming_the_table(path):
    with pytest.raises(mc.ProblemError, match="dynamics"):
        mc.solve(path)


def test_a_dict_solves_like_the_file():
    path = ROOT / "problems" / "beam_on_foundation.toml"
    from_file = mc.solve(path)
    from_dict = mc.solve(tomllib.loads(path.read_text()))
    from_text = mc.solve(path.read_text())
    for other in (from_dict, from_text):
        assert np.array_equal(other.displacement, from_file.displacement)
        assert np.array_equal(other.contact["force"], from_file.contact["force"])


def test_a_relative_mesh_path_is_the_problem_files(monkeypatch, tmp_path):
    # geometry.file = "plate_with_hole_gmsh.msh" sits beside the problem file: a path finds it
    # from any working directory, and with_values turns it into an absolute path in the dict.
    monkeypatch.chdir(tmp_path)
    path = ROOT / "problems" / "plate_with_hole_gmsh.toml"
    from_path = mc.solve(path)
    from_dict = mc.solve(mc.with_values(path, {"name": "plate_with_hole_gmsh"}))
    assert np.array_equal(from_dict.displacement, from_path.displacement)
    assert mc.with_values(path, {})["geometry"]["file"] == str(path.parent / "plate_with_hole_gmsh.msh")
    with pytest.raises(mc.ProblemError) as e:
        mc.solve(path.read_text())  # text has no folder: relative to the working directory
    assert e.value.field == "geometry.file"


def test_errors_name_the_field():
    base = tomllib.loads((ROOT / "problems" / "cantilever.toml").read_text())
    with pytest.raises(mc.ProblemError) as e:
        mc.solve(mc.with_values(base, {"material.poisson": 0.7}))
    assert e.value.field == "material.poisson"
    assert e.value.value == "0.7"
    assert isinstance(e.value, ValueError)
    with pytest.raises(mc.ProblemError) as e:
        mc.solve(mc.with_values(base, {"geometry.x": "abc"}))
    assert e.value.field == "geometry.x"
    with pytest.raises(mc.ProblemError) as e:
        mc.solve(mc.with_values(base, {"nodes.spacng": 0.5}))
    assert "spacng" in str(e.value)
    # A run-time failure names the keys that decide it.
    free = mc.with_values(base, {})
    free["boundary"] = [b for b in free["boundary"] if "displacement" not in b]
    with pytest.raises(mc.SolveError) as e:
        mc.solve(free)
    assert e.value.keys == "boundary[*].displacement"
    with pytest.raises(TypeError):
        mc.solve(42)


def test_with_values_sets_nested_and_indexed_keys():
    base = tomllib.loads((ROOT / "problems" / "beam_on_foundation.toml").read_text())
    p = mc.with_values(base, {"nodes.spacing": 0.5, "boundary[1].traction.y": -2.0})
    assert p["nodes"]["spacing"] == 0.5 and p["boundary"][1]["traction"]["y"] == -2.0
    assert base["nodes"]["spacing"] == 0.25, "the base is not modified"


def test_threads_solve_in_parallel_with_identical_results():
    from concurrent.futures import ThreadPoolExecutor

    path = ROOT / "problems" / "two_blocks.toml"
    with ThreadPoolExecutor(2) as pool:
        a, b = pool.map(mc.solve, [path, path])
    assert np.array_equal(a.displacement, b.displacement)
    assert np.array_equal(a.second_body()["displacement"], b.second_body()["displacement"])
