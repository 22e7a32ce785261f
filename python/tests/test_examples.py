"""The Python example scripts in examples/python/ run and produce their outputs."""
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]


def test_beam_gap_sweep_writes_its_plot(tmp_path):
    pytest.importorskip("matplotlib", reason="the example plots with matplotlib: pip install matplotlib")
    out = tmp_path / "x.png"
    run = subprocess.run(
        [sys.executable, ROOT / "examples" / "python" / "beam_gap_sweep.py", "--spacing", "1.0", "--out", out],
        cwd=tmp_path,  # not python/: there `import mlpg_contact` would find the source folder
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert run.returncode == 0, run.stderr
    assert "total contact force F_c" in run.stdout and "sweep of 8 gaps" in run.stdout
    data = out.read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n"
    assert len(data) > 20_000, f"a {len(data)}-byte PNG: an empty figure?"
