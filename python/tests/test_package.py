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


def test_the_installed_wheel_is_abi3_and_under_12_mb():
    """The package as installed from its wheel (`pip install .`, `pip wheel .`): tagged for the
    stable ABI from CPython 3.11 on (one wheel for every later CPython), the extension module
    named for it, and its files under 12 MB uncompressed, so the compressed wheel is too (it was
    3.6 MB with a 10.1 MB extension, stripped, on 2026-11-28)."""
    import importlib.metadata

    dist = importlib.metadata.distribution("mlpg-contact")
    tags = [line.split(": ", 1)[1] for line in (dist.read_text("WHEEL") or "").splitlines() if line.startswith("Tag: ")]
    assert tags and all(t.startswith("cp311-abi3-") for t in tags), tags
    assert Path(mc._native.__file__).name.startswith("_native.abi3."), mc._native.__file__
    size = sum(f.size or 0 for f in dist.files or [])
    assert 1_000_000 < size < 12_000_000, size
