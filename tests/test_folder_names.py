"""Every command's default output folder follows one rule."""

from __future__ import annotations

from pathlib import Path

from qdsega.folder_names import default_folder


def test_the_rule_by_hand():
    assert default_folder("quadruped", settings=["memo"], seed=0) == Path(
        "runs/quadruped-memo-seed0"
    )
    rubble = Path("/anywhere/rubble.yaml")
    assert default_folder("snake5", world=rubble, settings=["memo"], seed=2) == Path(
        "runs/snake5-rubble-memo-seed2"
    )
    assert default_folder("quadruped_tripod", command="reform", world=rubble) == Path(
        "runs/reform-quadruped_tripod-rubble"
    )
    assert default_folder("hub2-servo8", command="design") == Path("runs/design-hub2-servo8")
