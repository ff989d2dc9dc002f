"""tools/diagrams.py draws each of the docs' pictures, refuses bad input in one line, and the
docs show every picture it draws with its command beside it."""

from __future__ import annotations

import re
import runpy
import shutil
import sys
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

from qdsega.adaptation.archive import Archive, grid_centroids
from qdsega.analysis.adaptation_plots import archive_heat_map, best_per_square

ROOT = Path(__file__).resolve().parents[2]
DIAGRAMS = runpy.run_path(str(ROOT / "tools" / "diagrams.py"), run_name="diagrams")
MAX_PNG_BYTES = 150_000
"""The largest picture docs/figures/ may hold."""


def main(monkeypatch, *args: str | Path) -> int:
    """``tools/diagrams.py ARGS``, in this process."""
    monkeypatch.setattr(sys, "argv", ["diagrams.py", *map(str, args)])
    return DIAGRAMS["main"]()


@pytest.mark.parametrize("command", ["loop", "memo"])
def test_the_diagrams_are_drawn_small(command, monkeypatch, tmp_path, capsys):
    out = tmp_path / f"{command}.png"
    assert main(monkeypatch, command, "--out", out) == 0
    assert str(out) in capsys.readouterr().out
    picture = Image.open(out)
    assert picture.size == (1200, 640) and picture.mode == "P"
    assert out.stat().st_size <= MAX_PNG_BYTES


def test_each_square_holds_the_farthest_elite_in_it():
    points = np.array([[0.05, 0.05], [0.06, 0.01], [1.0, 1.0], [0.3, 0.7]])
    grid = best_per_square(points, np.array([1.0, 2.0, 3.0, -1.0]), 10)
    assert grid[0, 0] == 2.0 and grid[9, 9] == 3.0  # the better of two; an edge counts inside
    assert grid[7, 3] == -1.0  # 0.3 and 0.7 in their own squares, not the ones below
    assert np.isnan(grid).sum() == 97


def test_an_archive_of_four_axes_is_drawn_as_six_maps(tmp_path):
    archive = Archive.empty(grid_centroids(4, 2), max_cycle=2, n_joints=1)
    archive.insert(np.array([[0]]), np.array([0.1, 0.9, 0.4, 0.6]), 0.8)
    archive.insert(np.array([[1]]), np.array([0.8, 0.2, 0.7, 0.3]), 0.2)
    record = {"formation": "quadruped", "descriptor": "duty factor per leg",
              "descriptor_names": ["L1", "L2", "R1", "R2"]}  # fmt: skip
    out = archive_heat_map(archive, record, tmp_path / "archive.png")
    assert Image.open(out).size[0] > 500


def test_bad_folders_are_one_line_and_status_2(monkeypatch, tmp_path, capsys):
    for command in ("archive", "adaptation", "report"):
        assert main(monkeypatch, command, tmp_path, "--out", tmp_path / "x.png") == 2
        error = capsys.readouterr().err
        assert (
            error.startswith(f"diagrams.py {command}: error: {tmp_path}") and error.count("\n") == 1
        )
    assert not (tmp_path / "x.png").exists()


def test_the_report_needs_chromium_and_says_so(monkeypatch, tmp_path, capsys):
    (tmp_path / "report.html").write_text("<html></html>")
    monkeypatch.setenv("PATH", str(tmp_path / "empty"))
    assert main(monkeypatch, "report", tmp_path, "--out", tmp_path / "shot.png") == 2
    assert "no Chromium on the PATH" in capsys.readouterr().err


FAKE_CHROMIUM = """\
import sys
from PIL import Image
args = dict(a.split("=", 1) for a in sys.argv[1:] if "=" in a)
width, height = map(int, args["--window-size"].split(","))
assert sys.argv[-1].startswith("file://") and sys.argv[-1].endswith("report.html")
Image.new("RGB", (width, height), "white").save(args["--screenshot"])
"""


def test_the_report_is_shot_at_the_window_size(monkeypatch, tmp_path):
    """With a stand-in for Chromium that draws a blank page of the window's size."""
    (tmp_path / "run").mkdir()
    (tmp_path / "run" / "report.html").write_text("<html></html>")
    fake = tmp_path / "bin" / "chromium"
    fake.parent.mkdir()
    fake.write_text(f"#!{sys.executable}\n{FAKE_CHROMIUM}")
    fake.chmod(0o755)
    monkeypatch.setenv("PATH", str(fake.parent))
    assert main(monkeypatch, "report", tmp_path / "run", "--out", tmp_path / "shot.png") == 0
    assert Image.open(tmp_path / "shot.png").size == DIAGRAMS["WINDOW"]
    taller = ("--window", "640x1000", "--out", tmp_path / "tall.png")
    assert main(monkeypatch, "report", tmp_path / "run", *taller) == 0
    assert Image.open(tmp_path / "tall.png").size == (640, 1000)


@pytest.mark.slow
@pytest.mark.skipif(shutil.which("chromium") is None, reason="no chromium on the PATH")
def test_chromium_shoots_a_page(tmp_path):
    (tmp_path / "report.html").write_text("<html><body><h1>qdsega run</h1></body></html>")
    out = DIAGRAMS["screenshot"](
        tmp_path / "report.html",
        tmp_path / "shot.png",
        chromium=shutil.which("chromium"),
        window=(320, 240),
    )
    assert Image.open(out).size == (320, 240)


def test_the_docs_show_every_figure_with_its_command():
    pages = {p: p.read_text(encoding="utf-8") for p in (ROOT / "docs").glob("*.md")}
    pages[ROOT / "README.md"] = (ROOT / "README.md").read_text(encoding="utf-8")
    linked = {
        Path(m).name for text in pages.values() for m in re.findall(r"figures/(\S+\.png)", text)
    }
    for figure in (ROOT / "docs" / "figures").glob("*.png"):
        assert figure.name in linked, f"{figure.name} is on no page"
        assert figure.stat().st_size <= MAX_PNG_BYTES, figure.name
    text = "\n".join(pages.values())
    for command in DIAGRAMS["NAMES"]:
        assert f"tools/diagrams.py {command}" in text, command
    for command in ("loop", "memo", "report"):  # drawn to their default names
        assert DIAGRAMS["NAMES"][command] in linked, command
