"""report.html in a real browser: headless Chromium loads the page, its DOM holds the result
table with the run's numbers and one inline SVG per plot, and a screenshot is not blank.

Needs `chromium` (Debian package; `.ci/run` installs it) or CHROMIUM=/path/to/chrome."""
import json
import os
import shutil
import struct
import subprocess
import zlib
from pathlib import Path

import pytest

import mlpg_contact as mc

ROOT = Path(__file__).resolve().parents[2]


def chromium() -> str:
    path = os.environ.get("CHROMIUM") or shutil.which("chromium") or shutil.which("chromium-browser")
    if not path:
        pytest.fail("headless Chromium not found: install the `chromium` package or set CHROMIUM")
    return path


def browser(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run(
        [chromium(), "--headless=new", "--no-sandbox", "--disable-gpu", "--hide-scrollbars", *args],
        capture_output=True,
        text=False,
        timeout=120,
    )


def png_pixels(path: Path):
    """(width, height, rows of RGB(A) bytes) of an 8-bit PNG, decoded with zlib only."""
    data = path.read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n"
    pos, chunks, header = 8, [], None
    while pos < len(data):
        (length,) = struct.unpack(">I", data[pos : pos + 4])
        kind = data[pos + 4 : pos + 8]
        body = data[pos + 8 : pos + 8 + length]
        if kind == b"IHDR":
            header = struct.unpack(">IIBBBBB", body)
        elif kind == b"IDAT":
            chunks.append(body)
        pos += 12 + length
    width, height, depth, colour, _, _, interlace = header
    assert depth == 8 and interlace == 0 and colour in (2, 6)
    channels = 3 if colour == 2 else 4
    raw = zlib.decompress(b"".join(chunks))
    stride = width * channels
    rows, prev = [], bytearray(stride)
    for y in range(height):
        f = raw[y * (stride + 1)]
        line = bytearray(raw[y * (stride + 1) + 1 : (y + 1) * (stride + 1)])
        for i in range(stride):
            a = line[i - channels] if i >= channels else 0
            b = prev[i]
            c = prev[i - channels] if i >= channels else 0
            if f == 1:
                line[i] = (line[i] + a) & 255
            elif f == 2:
                line[i] = (line[i] + b) & 255
            elif f == 3:
                line[i] = (line[i] + (a + b) // 2) & 255
            elif f == 4:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                line[i] = (line[i] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        rows.append(bytes(line))
        prev = line
    return width, height, channels, rows


def test_report_renders_in_headless_chromium(tmp_path):
    result = mc.solve(ROOT / "problems" / "cattaneo_mindlin.toml")
    page = result.report(tmp_path / "out")
    assert page.name == "report.html" and page.is_file()
    text = page.read_text()
    assert "http://" not in text.replace("http://www.w3.org", "") and "https://" not in text, "self-contained"
    summary = json.loads((tmp_path / "out" / "summary.json").read_text())
    # The DOM as the browser built it.
    dom = browser("--dump-dom", page.as_uri())
    assert dom.returncode == 0, dom.stderr.decode(errors="replace")
    dom = dom.stdout.decode()
    assert dom.count("<svg") >= 6, "one inline SVG per plot"
    assert 'id="results"' in dom and 'id="timings"' in dom
    force = summary["contact"]["total_force"]
    # The page prints 6 significant digits.
    assert f">{force:.6g}<" in dom, force
    assert "stick zones" in dom and "Coulomb friction μ = 0.3" in dom
    # A screenshot that is not blank: enough non-white pixels, and colour (the plots).
    shot = tmp_path / "shot.png"
    run = browser("--window-size=1200,2400", f"--screenshot={shot}", page.as_uri())
    assert run.returncode == 0 and shot.is_file(), run.stderr.decode(errors="replace")
    width, height, channels, rows = png_pixels(shot)
    non_white = coloured = 0
    for row in rows[::4]:
        for x in range(0, width * channels, 4 * channels):
            r, g, b = row[x], row[x + 1], row[x + 2]
            non_white += (r, g, b) != (255, 255, 255)
            coloured += max(r, g, b) - min(r, g, b) > 60
    sampled = (height // 4) * (width // 4)
    assert non_white > 0.05 * sampled, f"{non_white} of {sampled} sampled pixels are not white"
    assert coloured > 0.01 * sampled, f"only {coloured} coloured pixels: no plots drawn?"


def test_cli_report_flag(tmp_path):
    binary = Path(os.environ.get("MLPG_CONTACT_BIN", ROOT / "target" / "release" / "mlpg-contact"))
    subprocess.run([binary, ROOT / "problems" / "cantilever.toml", "--out", tmp_path / "o", "--report", "--quiet"], check=True)
    html = (tmp_path / "o" / "report.html").read_text()
    assert html.startswith("<!DOCTYPE html>") and html.rstrip().endswith("</html>")
    assert "<h2>Results</h2>" in html and html.count("<svg") >= 2
