"""Every joint of a body reaches its levels without the body hitting itself, or
``qdsega assemble`` names the joint, the level and the units in the way."""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest
from helpers import SHIPPED_FORMATIONS

from qdsega.assembly import AssembledRobot, assemble
from qdsega.cli import main
from qdsega.description import load_formation
from qdsega.description.shipped import ASSEMBLIES_DIR
from qdsega.simulation.reach import unreachable_levels
from qdsega.simulation.settings import PhysicsSettings

LEFT_LEGS = """\
  - {name: "L{i}", repeat: [1, 2], template: leg, parent: "body{i}", connector: left,
     side: left}
"""


def _quadruped(project: Path, name: str, *, replace: tuple[str, str]) -> Path:
    """The shipped quadruped as ``assemblies/<name>.yaml`` of ``project``, built from the
    project's units, with one text replaced."""
    text = (ASSEMBLIES_DIR / "quadruped.yaml").read_text(encoding="utf-8")
    text = text.replace("name: quadruped\n", f"name: {name}\nunits_dir: ../units\n")
    assert replace[0] in text
    file = project / "assemblies" / f"{name}.yaml"
    file.write_text(text.replace(*replace), encoding="utf-8")
    return file


def _turned_connector(project: Path) -> Path:
    """The quadruped whose back hub has its left leg connector turned into the hub: leg L2
    folds across body2 and out of its right side."""
    folder = project / "units" / "hub_turned"
    shutil.copytree(project / "units" / "hub", folder)
    unit = folder / "unit.yaml"
    left = "left:  {xyz_m: [-0.09, 0.05, 0.0], rpy_deg: [0, 0, -90]}"
    assert left in unit.read_text()
    unit.write_text(unit.read_text().replace(left, left.replace("-90]", "90]")))
    back_hub = "repeat: [2, 2], unit: hub,"
    return _quadruped(
        project, "quadruped_bad", replace=(back_hub, back_hub.replace("hub", "hub_turned"))
    )


def _robot(file: Path) -> AssembledRobot:
    """The formation in ``file``, assembled."""
    return assemble(load_formation(file))


@pytest.mark.parametrize("file", SHIPPED_FORMATIONS, ids=lambda f: f.stem)
def test_every_shipped_formation_reaches_every_level(file: Path) -> None:
    assert unreachable_levels(_robot(file)) == []


def test_a_leg_connector_turned_into_the_hub_is_caught(project: Path) -> None:
    blocked = unreachable_levels(_robot(_turned_connector(project)))
    first = blocked[0]
    assert (first.joint, first.level) == ("L2_swing_joint", 0)
    assert first.level_deg == pytest.approx(-15.0)
    assert (first.unit, first.other) == ("L2_lift", "body2")
    assert first.depth_m > 0.01
    assert str(first) == (
        "joint L2_swing_joint cannot reach level 0 (-15 deg): unit L2_lift hits unit body2"
    )
    # Only the turned leg and the leg it now lies across: the front legs move freely.
    assert {b.joint for b in blocked} <= {"L2_swing_joint", "L2_lift_joint", "R2_swing_joint"}


ONE_LEG_WIDE = (
    "  - {name: L1, template: leg, parent: body1, connector: left, side: left,\n"
    "     overrides: {swing: {levels_deg: [-15, 45]}}}\n"
    "  - {name: L2, template: leg, parent: body2, connector: left, side: left}\n"
)
"""Leg L1 swings back 45 deg, through leg L2: one blocked level."""


def test_only_the_level_out_of_reach_is_blocked_and_where_it_hits(project: Path) -> None:
    """Leg L1 swung back 45 deg hits leg L2 on the way, at 30 deg; its other level is free."""
    wide = _quadruped(project, "wide", replace=(LEFT_LEGS, ONE_LEG_WIDE))
    blocked = unreachable_levels(_robot(wide))
    (only,) = blocked
    assert (only.joint, only.level) == ("L1_swing_joint", 1)
    assert (only.unit, only.other) == ("L1_lift", "L2_lift")
    assert only.level_deg == pytest.approx(45.0)
    assert 15.0 < only.at_deg < 45.0
    assert str(only).endswith(f"unit L1_lift hits unit L2_lift at {only.at_deg:.0f} deg")


def test_without_self_collision_every_level_is_reachable(project: Path) -> None:
    robot = _robot(_turned_connector(project))
    assert unreachable_levels(robot, PhysicsSettings(self_collision=False)) == []


def test_assemble_refuses_the_body_in_one_line_and_writes_nothing(
    project: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    file = _turned_connector(project)
    out = project / "out"
    assert main(["assemble", "snake5", str(file), "--out-dir", str(out)]) == 2
    captured = capsys.readouterr()
    lines = captured.err.splitlines()
    assert len(lines) == 1, captured.err
    assert lines[0].startswith(f"qdsega assemble: error: {file}:")
    assert (
        "joint L2_swing_joint cannot reach level 0 (-15 deg): unit L2_lift hits unit body2"
        in lines[0]
    )
    assert (out / "snake5.urdf").is_file()
    assert not (out / "quadruped_bad.urdf").exists()


def test_allow_blocked_assembles_the_body_with_the_same_message_as_a_warning(
    project: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """Neighbouring legs that overlap at one swing level: refused, or with --allow-blocked
    assembled, the refusal's message a warning."""
    file = _quadruped(project, "wide", replace=(LEFT_LEGS, ONE_LEG_WIDE))
    out = project / "out.urdf"
    assert main(["assemble", str(file), "-o", str(out)]) == 2
    (refusal,) = capsys.readouterr().err.splitlines()
    assert not out.exists()
    assert main(["assemble", str(file), "-o", str(out), "--allow-blocked"]) == 0
    captured = capsys.readouterr()
    (warning,) = captured.err.splitlines()
    message = refusal.removeprefix("qdsega assemble: error: ")
    assert message.endswith(" (--allow-blocked goes on regardless)")
    message = message.removesuffix(" (--allow-blocked goes on regardless)")
    assert message.startswith(f"{file}:") and "cannot reach level 1 (45 deg)" in message
    assert warning.startswith(f"qdsega assemble: warning: {message}; going on (--allow-blocked)")
    assert out.is_file() and "wide" in captured.out
