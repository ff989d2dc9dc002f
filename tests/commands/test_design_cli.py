"""``qdsega design``'s own part, in-process: its search is reform's (test_reform_cli.py)."""

from __future__ import annotations

from collections import Counter
from pathlib import Path

import pytest

from qdsega.description import load_formation


def test_design_writes_its_first_body_and_searches_from_it(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
):
    """design's own part: the bag, the first body's file, the search started from it, the
    verdict. The search itself is reform's, run end to end in
    test_reform_cli.py."""
    from qdsega.assembly import assemble
    from qdsega.cli import main
    from qdsega.commands import design
    from qdsega.simulation.reach import check_reach

    searched = []

    def search(args, file, out):  # reform's search, as design calls it
        body = load_formation(file)
        check_reach(assemble(body))  # the first body assembles and reaches its levels
        searched.append((body, out))
        winner = {"name": "c01", "reformed": True, "moves": [{}], "distance_m": 1.5}
        return {"inputs": {"formation": body.name}, "winner": winner, "wall_s": 60.0}

    monkeypatch.setattr(design, "search", search)
    monkeypatch.chdir(tmp_path)
    assert main(["design", "hub=2", "servo=5"]) == 0
    ((body, out),) = searched
    assert out == Path("runs/design-hub2-servo5")
    assert Counter(u.unit_type.name for u in body.units) == {"hub": 2, "servo": 5}
    assert len(body.legs) == 2  # two legs of two servos, the fifth servo a tail
    assert load_formation(out / "first.yaml").name == "design_hub2-servo5"
    assert "design_hub2-servo5: designed c01 (1 move from it), 1.5000 m" in capsys.readouterr().out
    assert main(["design", "gripper=1"]) == 2  # an unknown unit type: one line, exit 2
