"""The package's metadata: one version everywhere, and the licence files the metadata names."""
import tomllib
from pathlib import Path

import mlpg_contact as mc

ROOT = Path(__file__).resolve().parents[2]


def test_one_version_everywhere():
    pyproject = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))
    crate = tomllib.loads((ROOT / "Cargo.toml").read_text(encoding="utf-8"))
    bindings = tomllib.loads((ROOT / "python" / "Cargo.toml").read_text(encoding="utf-8"))
    assert mc.__version__ == pyproject["project"]["version"]
    assert mc.__version__ == crate["package"]["version"] == bindings["package"]["version"]
    # The solver that answers is the same release: summary.json names it.
    summary = mc.solve(ROOT / "problems" / "cantilever.toml").summary
    assert summary["program"] == {"name": "mlpg-contact", "version": mc.__version__}


def test_licence_files_and_readme_exist():
    pyproject = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))
    crate = tomllib.loads((ROOT / "Cargo.toml").read_text(encoding="utf-8"))
    assert pyproject["project"]["license"]["text"] == crate["package"]["license"] == "MIT OR Apache-2.0"
    for name in ["LICENSE-MIT", "LICENSE-APACHE"]:
        assert (ROOT / name).is_file(), name
    assert "Apache License" in (ROOT / "LICENSE-APACHE").read_text(encoding="utf-8")
    assert (ROOT / pyproject["project"]["readme"]).is_file()
    assert (ROOT / crate["package"]["readme"]).is_file()
