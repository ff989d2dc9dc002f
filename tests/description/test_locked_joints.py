"""A broken joint, locked at an angle: a fixed joint where the working one would stand, no
longer an action; a leg with one is a broken leg; a bad angle is one line of error."""

import math
import textwrap

import numpy as np
import pytest

from qdsega.assembly import assemble
from qdsega.description import load_formation
from qdsega.description.shipped import UNITS_DIR
from qdsega.errors import FormationError
from qdsega.simulation.bullet import BulletSimulation

SNAKE = """\
name: s
light: {{distance_m: 5}}
units_dir: {units}
units:
  - {{name: u1, unit: servo}}
  - {{name: u2, unit: servo, parent: u1, connector: back, axis: yaw, levels_deg: [-20, 0, 20]}}
  - {{name: u3, unit: servo, parent: u2, connector: back, axis: yaw, {joint}}}
  - {{name: u4, unit: servo, parent: u3, connector: back, axis: pitch, levels_deg: [-10, 10]}}
"""

LEGGED = """\
name: walker
light: {{distance_m: 5}}
units_dir: {units}
templates:
  leg:
    leg: {{swing: swing, lift: lift}}
    units:
      - {{name: swing, unit: servo, axis: yaw, levels_deg: [-15, 15]}}
      - {{name: lift, unit: servo, parent: swing, connector: back, axis: pitch,
         levels_deg: [-35, 5]}}
units:
  - {{name: body1, unit: hub}}
  - {{name: body2, unit: hub, parent: body1, connector: back}}
  - {{name: L1, template: leg, parent: body1, connector: left, side: left}}
  - {{name: R1, template: leg, parent: body1, connector: right, side: right}}
  - {{name: L2, template: leg, parent: body2, connector: left, side: left,
     overrides: {{lift: {{locked_deg: {lift}}}}}}}
  - {{name: R2, template: leg, parent: body2, connector: right, side: right}}
"""


def _write(tmp_path, text: str, **fields) -> str:
    file = tmp_path / "robot.yaml"
    file.write_text(textwrap.dedent(text).format(units=UNITS_DIR, **fields))
    return file


def test_a_locked_joint_is_fixed_and_no_longer_an_action(tmp_path):
    formation = load_formation(_write(tmp_path, SNAKE, joint="locked_deg: 15"))
    assert [j.name for j in formation.joints] == ["u2_joint", "u4_joint"]
    locked = formation.units[2]
    assert locked.locked_rad == pytest.approx(math.radians(15)) and locked.levels_rad == ()
    assert not locked.is_actuated
    urdf = assemble(formation).urdf
    assert '<joint name="u3_joint" type="fixed">' in urdf


def test_a_locked_joint_holds_the_pose_the_working_joint_takes_at_that_angle(tmp_path):
    """Every unit sits where it sits when the working joint is commanded to the angle."""
    working = load_formation(_write(tmp_path, SNAKE, joint="levels_deg: [-15, 0, 15]"))
    locked = load_formation(_write(tmp_path, SNAKE, joint="locked_deg: 15"))
    positions = []
    for formation, angles in ((working, [0.2, math.radians(15), 0.1]), (locked, [0.2, 0.1])):
        with BulletSimulation(robot=assemble(formation)) as sim:
            sim.reset(angles)
            xyz, quaternions = sim.unit_states()
            positions.append((xyz - xyz[0], quaternions))
    np.testing.assert_allclose(positions[0][0], positions[1][0], atol=1e-6)
    np.testing.assert_allclose(np.abs(positions[0][1]), np.abs(positions[1][1]), atol=1e-6)


def test_a_leg_with_a_locked_joint_is_broken_and_its_units_are_not_trunk(tmp_path):
    formation = load_formation(_write(tmp_path, LEGGED, lift=-35))
    assert [leg.name for leg in formation.legs] == ["L1", "R1", "R2"]
    assert [leg.name for leg in formation.broken_legs] == ["L2"]
    assert [u.name for u in formation.trunk_units] == ["body1", "body2"]
    assert "L2_swing_joint" in [j.name for j in formation.joints]
    assert "L2_lift_joint" not in [j.name for j in formation.joints]
    assert formation.rest_levels() == (0,) * 7  # the broken leg's swing stands forward too


@pytest.mark.parametrize(
    ("text", "fields", "message"),
    [
        (SNAKE, {"joint": "locked_deg: 120"}, "locked angle 120 deg is outside the joint limits"),
        (LEGGED, {"lift": "-95"}, "locked angle -95 deg is outside the joint limits"),
        (SNAKE, {"joint": "locked_deg: abc"}, "locked_deg"),
    ],
)
def test_a_bad_locked_angle_is_one_line_naming_the_key(tmp_path, text, fields, message):
    with pytest.raises(FormationError) as error:
        load_formation(_write(tmp_path, text, **fields))
    line = str(error.value)
    assert "\n" not in line and message in line and "locked_deg" in line


def test_a_locked_angle_on_a_unit_without_joint_is_refused(tmp_path):
    text = SNAKE.replace("{{name: u1, unit: servo}}", "{{name: u1, unit: servo, locked_deg: 0}}")
    with pytest.raises(FormationError, match="'locked_deg' given but unit 'u1' is the root"):
        load_formation(_write(tmp_path, text, joint="levels_deg: [0, 10]"))
