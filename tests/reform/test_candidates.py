"""Candidate bodies, by hand on a tiny body; units conserved; sides and mirrored levels; whole
shapes; spares."""

from __future__ import annotations

import math
from collections import Counter
from pathlib import Path

import pytest
from helpers import BIPED

from qdsega.description import load_formation, resolve_formation
from qdsega.description.formation_writer import formation_yaml
from qdsega.errors import ConfigError, FormationError
from qdsega.msm.legs import LegLayout
from qdsega.reform.arrangement import Move, Place
from qdsega.reform.candidates import CHAIN, Candidates, moves_from, whole_shapes
from qdsega.reform.design import first_body
from qdsega.reform.material import material_of, parse_units


@pytest.fixture
def biped(tmp_path: Path) -> Path:
    file = tmp_path / "biped.yaml"
    file.write_text(BIPED)
    return file


def degrees(levels: tuple[float, ...]) -> list[float]:
    return [round(math.degrees(a), 6) for a in levels]


def test_the_tiny_body_by_hand(biped: Path):
    material = material_of(load_formation(biped), {})
    start = material.start()
    assert [str(m) for m in moves_from(start)] == [
        "L1_swing: body1.left -> body1.back",
        "L1_swing: body1.left -> the spares",
        "R1_swing: body1.right -> body1.back",
        "R1_swing: body1.right -> the spares",
    ]
    found = Candidates(material, symmetric=True)
    found.first_round()
    # R1 behind is the mirror image of L1 behind; one leg set aside is one body either way;
    # the chain hub-L1-R1 and the pairs shape are bodies found already or the body itself
    assert [(c.name, [str(m) for m in c.moves], c.how) for c in found.found] == [
        ("c00", [], "the body as it is"),
        ("c01", ["L1_swing: body1.left -> body1.back"], "moved"),
        ("c02", ["L1_swing: body1.left -> the spares"], "moved"),
        (
            "c03",
            ["L1_swing: body1.left -> body1.back", "R1_swing: body1.right -> L1_lift.back"],
            CHAIN,
        ),
    ]
    behind = found.found[1].arrangement.formation("b", "")
    assert [(leg.name, leg.side) for leg in behind.legs] == [("L1", "left"), ("R1", "right")]
    chain = found.found[3].arrangement.formation("c", "")
    assert chain.legs == () and [u.name for u in chain.units] == [
        "body1", "L1_swing", "L1_lift", "R1_swing", "R1_lift"
    ]  # fmt: skip
    # a leg's units in a chain: levels centred on straight, spanning what the leg's did
    assert [degrees(j.levels_rad) for j in chain.joints] == [[-15, 0, 15], [-20, 0, 20]] * 2


def test_without_the_mirror_a_body_and_its_mirror_image_are_two(biped: Path):
    found = Candidates(material_of(load_formation(biped), {}), symmetric=False)
    found.first_round()
    assert len(found.found) == 6  # c01, c02 and their mirror images, and the chain


def test_a_leg_moved_to_the_other_side_is_mirrored(biped: Path):
    material = material_of(load_formation(biped), {})
    aside = material.start().moved(Move("R1_swing", Place("body1", "right"), None))
    moved = aside.moved(Move("L1_swing", Place("body1", "left"), Place("body1", "right")))
    body = moved.formation("m", "")
    assert [(leg.name, leg.side) for leg in body.legs] == [("L1", "right")]
    assert degrees(body.units_by_name["L1_swing"].levels_rad) == [15, -15]  # as R1's were
    assert degrees(body.units_by_name["L1_lift"].levels_rad) == [-35, 5]  # pitch: as it was
    assert moved.key(mirror=True) == aside.key()


def test_a_move_that_cannot_be_made_is_refused(biped: Path):
    start = material_of(load_formation(biped), {}).start()
    taken = Move("L1_swing", Place("body1", "left"), Place("body1", "right"))
    into_itself = Move("L1_swing", Place("body1", "left"), Place("L1_lift", "back"))
    for move in (taken, into_itself, Move("body1", None, Place("L1_lift", "back"))):
        assert not start.can(move)
        with pytest.raises(ValueError, match="cannot move"):
            start.moved(move)


@pytest.mark.parametrize("spares", [{}, {"servo": 3, "hub": 1}])
def test_no_candidate_uses_a_unit_that_is_not_there(spares: dict[str, int]):
    formation = load_formation(resolve_formation("quadruped_tripod"))
    material = material_of(formation, spares)
    have = Counter(u.unit_type.name for u in material.units.values())
    assert have == Counter(u.unit_type.name for u in formation.units) + Counter(spares)
    found = Candidates(material, symmetric=True)
    found.next_round(found.first_round())
    assert len(found.found) > 20
    for candidate in found.found:
        body = candidate.arrangement.formation(candidate.name, "")
        names = [u.name for u in body.units]
        assert len(set(names)) == len(names)
        for unit in body.units:  # each is a unit of the material, of its own type
            assert unit.unit_type == material.units[unit.name].unit_type
        assert Counter(u.unit_type.name for u in body.units) <= have


def test_spares_make_a_leg_and_a_spare_unit():
    formation = load_formation(resolve_formation("quadruped_tripod"))
    material = material_of(formation, {"servo": 3})
    assert [leg.name for leg in material.legs] == ["L1", "L2", "R1", "S1"]
    assert [n for n in material.units if n not in formation.units_by_name] == [
        "S1_swing", "S1_lift", "spare_servo"
    ]  # fmt: skip
    start = material.start()
    assert start.tops() == ("S1_swing", "spare_servo")
    assert "S1_swing: the spares -> body2.right" in [str(m) for m in moves_from(start)]


def test_a_spare_leg_names_the_joints_it_has_once_attached(tmp_path):
    # A spare leg's top hangs from nothing until a move attaches it: its leg used to name no
    # swing joint, and the body with it attached failed to be written or laid out (KeyError).
    material = material_of(load_formation(resolve_formation("quadruped_tripod")), {"servo": 2})
    spare = material.legs[-1]
    assert (spare.swing_joint, spare.lift_joint) == ("S1_swing_joint", "S1_lift_joint")
    start = material.start()
    move = next(m for m in moves_from(start) if str(m) == "S1_swing: the spares -> body2.right")
    body = start.moved(move).formation("four_legs", "a spare leg on body2")
    layout = LegLayout.from_formation(body, both_sides=False)
    assert len(layout.swing) == 4
    assert body.joints[layout.swing[-1]].name == "S1_swing_joint"
    file = tmp_path / "four_legs.yaml"
    file.write_text(formation_yaml(body, file), encoding="utf-8")
    assert load_formation(file).legs[-1].swing_joint == "S1_swing_joint"


def test_whole_shapes_of_the_hexapod_that_lost_a_leg():
    material = material_of(load_formation(resolve_formation("hexapod_lost_leg")), {})
    shapes = dict(whole_shapes(material))
    pairs = shapes["legs in pairs, one behind"].formation("p", "")
    places = {u.name: (u.parent, u.connector) for u in pairs.units if u.name.endswith("swing")}
    assert sorted(places.values()) == [
        ("body1", "left"), ("body1", "right"), ("body2", "left"), ("body2", "right"),
        ("body3", "back"),
    ]  # fmt: skip
    chain = shapes[CHAIN].formation("c", "")
    assert chain.legs == () and all(u.connector in (None, "back") for u in chain.units)


def test_bad_spares_are_refused_in_one_line():
    with pytest.raises(ConfigError, match="expected TYPE=N"):
        parse_units(["servo"])
    with pytest.raises(ConfigError, match="expected TYPE=N"):
        parse_units(["servo=0"])
    with pytest.raises(ConfigError, match="given twice"):
        parse_units(["servo=1", "servo=2"])
    with pytest.raises(FormationError, match="--spare gripper: unknown unit type 'gripper'"):
        material_of(load_formation(resolve_formation("quadruped")), {"gripper": 1})


def test_a_first_body_from_a_bag_of_units():
    body = first_body({"hub": 2, "servo": 7})
    assert [u.name for u in body.units] == [
        "body1", "body2", "L1_swing", "L1_lift", "R1_swing", "R1_lift", "L2_swing", "L2_lift",
        "tail1",
    ]  # fmt: skip
    assert [(leg.name, leg.side) for leg in body.legs] == [
        ("L1", "left"), ("R1", "right"), ("L2", "left")
    ]  # fmt: skip
    units = body.units_by_name
    assert degrees(units["R1_swing"].levels_rad) == [15, -15]
    assert (units["tail1"].parent, units["tail1"].connector) == ("body2", "back")
    chain = first_body({"servo": 3})  # no passive unit: one chain
    assert [(u.name, u.parent) for u in chain.units] == [
        ("body1", None), ("tail1", "body1"), ("tail2", "tail1")
    ]  # fmt: skip
    with pytest.raises(ConfigError, match="no joint"):
        first_body({"hub": 3})
    with pytest.raises(FormationError, match="gripper: unknown unit type"):
        first_body({"gripper": 1})
