import math

import pytest
from helpers import SHIPPED_FORMATIONS

from qdsega.description import load_formation
from qdsega.errors import FormationError

EXPECTED_JOINTS = {
    "snake5": 4,
    "snake6": 5,
    "snake10": 9,
    "legged12": 24,
    "legged12_locked_leg": 22,
    "quadruped": 8,
    "quadruped_tripod": 6,
    "hexapod": 12,
    "hexapod_lost_leg": 10,
}
EXPECTED_LEGS = {
    "snake5": 0,
    "snake6": 0,
    "snake10": 0,
    "legged12": 12,
    "legged12_locked_leg": 11,
    "quadruped": 4,
    "quadruped_tripod": 3,
    "hexapod": 6,
    "hexapod_lost_leg": 5,
}


def test_every_expected_formation_is_shipped():
    assert {f.stem for f in SHIPPED_FORMATIONS} >= set(EXPECTED_JOINTS)


@pytest.mark.parametrize("file", SHIPPED_FORMATIONS, ids=lambda f: f.stem)
def test_shipped_formation_reads(file):
    formation = load_formation(file)
    assert formation.name == file.stem
    assert len(formation.joints) == EXPECTED_JOINTS[formation.name]
    assert len(formation.legs) == EXPECTED_LEGS[formation.name]
    assert formation.root.parent is None
    placed = set()
    for unit in formation.units:  # parents come before children
        assert unit.parent is None or unit.parent in placed
        placed.add(unit.name)
    assert file.read_text().startswith("#"), "shipped formations start with a comment header"


def test_snake5_has_the_papers_levels():
    formation = load_formation("assemblies/snake5.yaml")
    for joint in formation.joints:
        assert [round(math.degrees(a)) for a in joint.levels_rad] == list(range(-20, 21, 5))
    assert all(u.axis == (0.0, 0.0, 1.0) for u in formation.units[1:])


def test_legged12_legs_follow_the_leg_convention():
    formation = load_formation("assemblies/legged12.yaml")
    assert [leg.name for leg in formation.legs_on("left")] == [f"L{i}" for i in range(1, 7)]
    assert [leg.name for leg in formation.legs_on("right")] == [f"R{i}" for i in range(1, 7)]
    by_name = {j.name: j for j in formation.joints}
    for leg in formation.legs:
        swing = by_name[leg.swing_joint].levels_rad
        lift = by_name[leg.lift_joint].levels_rad
        assert len(swing) == len(lift) == 2
        # Left legs trail along -y of the swing unit; mirrored levels keep [forward, back].
        assert swing == tuple(
            math.radians(d) for d in ((-15, 15) if leg.side == "left" else (15, -15))
        )
        assert lift == (math.radians(-35), math.radians(5))


def test_rest_levels_stand_on_legs_and_straighten_snakes():
    legged = load_formation("assemblies/legged12.yaml")
    assert legged.rest_levels() == (0,) * 24
    snake = load_formation("assemblies/snake5.yaml")
    assert snake.rest_levels() == (4, 4, 4, 4)


def test_repeat_and_template_expand(write_formation):
    file = write_formation(
        """
        name: chain
        light: {distance_m: 3, bearing_deg: 90}
        templates:
          arm:
            units:
              - {name: a, unit: servo, axis: pitch, levels_deg: [0, 10]}
              - {name: b, unit: servo, parent: a, connector: back, axis: [0, 0, 2],
                 levels_deg: {min: -10, max: 10, step: 10}}
        units:
          - {name: base1, unit: hub}
          - {name: "base{i}", repeat: [2, 3], unit: hub, parent: "base{i-1}", connector: back}
          - {name: "arm{i}", repeat: [1, 2], template: arm, parent: "base{i+1}",
             connector: left, overrides: {b: {levels_deg: [5]}}}
        """
    )
    formation = load_formation(file)
    names = [u.name for u in formation.units]
    assert names == ["base1", "base2", "base3", "arm1_a", "arm1_b", "arm2_a", "arm2_b"]
    by_name = {u.name: u for u in formation.units}
    assert by_name["arm2_a"].parent == "base3"
    assert by_name["arm1_b"].axis == (0.0, 0.0, 1.0)
    assert by_name["arm1_b"].levels_rad == (math.radians(5),)
    assert by_name["arm1_a"].levels_rad == (0.0, math.radians(10))
    assert formation.light.position_m == pytest.approx((0.0, 3.0))


def test_units_may_be_declared_before_their_parent(write_formation):
    file = write_formation(
        """
        name: backwards
        light: {distance_m: 3}
        units:
          - {name: tail, unit: servo, parent: head, connector: back, axis: yaw, levels_deg: [0]}
          - {name: head, unit: servo}
        """
    )
    assert [u.name for u in load_formation(file).units] == ["head", "tail"]


def test_error_names_file_line_and_key(write_formation):
    file = write_formation(
        """
        name: bad
        light: {distance_m: 3}
        units:
          - {name: head, unit: servo}
          - name: tail
            unit: servo
            parent: head
            connector: back
            axis: yaw
            levels_deg: [0, 95]
        """
    )
    with pytest.raises(FormationError) as info:
        load_formation(file)
    line = file.read_text().splitlines().index("    levels_deg: [0, 95]") + 1
    expected = f"{file}:{line}: units[1].levels_deg[1]: level 95 deg is outside the joint limits"
    assert str(info.value).startswith(expected)


def test_trunk_is_everything_but_the_legs():
    legged = load_formation("assemblies/legged12.yaml")
    assert [u.name for u in legged.trunk_units] == [f"body{i}" for i in range(1, 7)]
    assert legged.legs[0].units == ("L1_swing", "L1_lift")
    snake = load_formation("assemblies/snake5.yaml")
    assert snake.trunk_units == snake.units
