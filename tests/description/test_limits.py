"""Hostile or mistaken numbers are refused as they are read, before anything is expanded."""

import math
import time
from pathlib import Path

import pytest

from qdsega.cli import main
from qdsega.description import load_formation
from qdsega.description.limits import MAX_LEVELS, MAX_UNITS
from qdsega.errors import FormationError
from qdsega.yaml_reader import MAX_FILE_BYTES, Interval

SNAKE = """\
name: snake
light: {distance_m: 3}
units:
  - {name: u1, unit: servo}
  - {name: "u{i}", repeat: [2, 5], unit: servo, parent: "u{i-1}", connector: back, axis: yaw,
     levels_deg: {min: -20, max: 20, step: 5}}
"""


def _refused(write_formation, text: str) -> str:
    file = write_formation(text)
    start = time.perf_counter()
    with pytest.raises(FormationError) as info:
        load_formation(file)
    assert time.perf_counter() - start < 20.0  # the guarded cases took over 60 s
    return str(info.value)


def test_interval_reads_as_written():
    assert str(Interval(0, 100, open_low=True)) == "(0, 100]"
    assert str(Interval(-180, 180)) == "[-180, 180]"
    assert 0 not in Interval(0, 1, open_low=True) and 0 in Interval(0, 1)
    assert math.nan not in Interval(-math.inf, math.inf)


def test_a_billion_levels_are_refused_at_once(project, write_formation, capsys):
    """Before the fix this expanded 200 million levels: more than 60 s and 17 GB."""
    text = SNAKE.replace("min: -20", "min: -1000000000")
    file = write_formation(text)
    start = time.perf_counter()
    assert main(["assemble", str(file), "-o", str(project / "out.urdf")]) == 2
    assert time.perf_counter() - start < 20.0  # the guarded cases took over 60 s
    err = capsys.readouterr().err
    assert err.count("\n") == 1
    assert "robot.yaml:6: units[1].levels_deg.min: must be in [-360, 360], got -1000000000" in err
    assert not (project / "out.urdf").exists()


@pytest.mark.parametrize(
    ("old", "new", "expected"),
    [
        ("min: -20", "min: -100", "units[1].levels_deg.min: level -100 deg is outside the joint"),
        ("step: 5", "step: 0.000001", f"gives 40000001 levels; a joint has at most {MAX_LEVELS}"),
        ("step: 5", "step: 5.0e-324", "levels_deg.step: gives inf levels"),
        ("step: 5", "step: .nan", "levels_deg.step: expected a number, got nan"),
        ("max: 20", "max: .inf", "levels_deg.max: must be in [-360, 360], got inf"),
        (
            "distance_m: 3",
            "distance_m: 1.0e+400",
            "light.distance_m: must be in (0, 10000], got inf",
        ),
        ("distance_m: 3", "distance_m: " + "9" * 400, "light.distance_m: must be in (0, 10000]"),
        ("distance_m: 3", "distance_m: " + "9" * 5000, "a number of 5000 digits is too long"),
        ("distance_m: 3", "distance_m: 3, bearing_deg: -1.0e+9", "bearing_deg: must be in [-360"),
        ("repeat: [2, 5]", "repeat: [2, 1000000000]", "repeat[1]: must be in [-1e+06, 1e+06]"),
        ("repeat: [2, 5]", "repeat: [2, 999999]", f"more than {MAX_UNITS} units"),
        ("axis: yaw", "axis: [1.0e+300, 0, 0]", "axis[0]: must be in [-1000, 1000]"),
        ("axis: yaw", "axis: [1.0e-300, 0, 0]", "axis vector must not be zero"),
    ],
)
def test_numbers_are_bounded(write_formation, old, new, expected):
    assert old in SNAKE
    assert expected in _refused(write_formation, SNAKE.replace(old, new))


def test_level_lists_are_capped(write_formation):
    levels = "[" + ", ".join(str(k) for k in range(-40, 40)) + "]"
    text = SNAKE.replace("{min: -20, max: 20, step: 5}", levels)
    assert "80 levels; a joint has at most 64" in _refused(write_formation, text)


def test_templates_count_toward_the_unit_cap(write_formation):
    text = SNAKE + (
        "  - {name: 'arm{i}', repeat: [1, 70], template: arm, parent: u1, connector: left}\n"
        "templates:\n"
        "  arm:\n"
        "    units:\n"
        "      - {name: a, unit: hub}\n"
        "      - {name: b, unit: hub, parent: a, connector: back}\n"
    )
    assert "units[2].repeat: more than 128 units" in _refused(write_formation, text)


def test_aliases_expand_like_their_anchors(write_formation):
    text = SNAKE.replace("levels_deg: {min: -20, max: 20, step: 5}", "levels_deg: &wave [-5, 5]")
    text += (
        "  - {name: arm, unit: servo, parent: u1, connector: left, axis: yaw, levels_deg: *wave}\n"
    )
    formation = load_formation(write_formation(text))
    assert {j.levels_rad for j in formation.joints} == {(math.radians(-5), math.radians(5))}


def test_an_alias_bomb_is_refused(write_formation):
    text = SNAKE + "".join(
        f"x{k}: &x{k} [{', '.join([f'*x{k - 1}'] * 9)}]\n" for k in range(1, 10)
    ).replace("*x0", "l")
    assert "more than 100000 values (aliases expanded)" in _refused(write_formation, text)


def test_an_alias_inside_its_own_anchor_is_refused(write_formation):
    message = _refused(write_formation, "name: &a [*a]\n")
    assert "robot.yaml:1: name[0]: a YAML alias inside its own anchor" in message


def test_deep_nesting_is_refused(write_formation):
    for depth in (40, 5000):
        text = "name: " + "[" * depth + "]" * depth + "\n"
        assert "nested deeper than 32 levels" in _refused(write_formation, text)


def test_big_files_are_refused(write_formation):
    text = SNAKE + "# " + "x" * MAX_FILE_BYTES + "\n"
    assert f"at most {MAX_FILE_BYTES}" in _refused(write_formation, text)


@pytest.mark.parametrize(
    ("old", "new", "expected"),
    [
        ("mass_kg: 0.15", "mass_kg: 1.0e+9", "mass_kg: must be in (0, 100]"),
        ("mass_kg: 0.15", "mass_kg: .nan", "mass_kg: expected a number, got nan"),
        ("lower_deg: -90", "lower_deg: -1000", "joint.lower_deg: must be in [-180, 180]"),
        ("effort_nm: 2.5", "effort_nm: .inf", "joint.effort_nm: must be in (0, 1000]"),
        ("velocity_rad_s: 5.8", "velocity_rad_s: 1.0e+6", "must be in (0, 100]"),
        ("[-0.10, 0.0, 0.0]", "[-1.0e+12, 0.0, 0.0]", "connectors.back.xyz_m[0]: must be in [-10"),
    ],
)
def test_unit_numbers_are_bounded(project, write_formation, old, new, expected):
    unit = _own_servo(project)
    assert old in unit.read_text()
    unit.write_text(unit.read_text().replace(old, new))
    assert expected in _refused(write_formation, OWN_SNAKE)


@pytest.mark.parametrize("name", ["../units/servo", "/etc", "..", "servo/.."])
def test_unit_types_are_folder_names(write_formation, name):
    text = SNAKE.replace("{name: u1, unit: servo}", f"{{name: u1, unit: '{name}'}}")
    assert "units[0].unit: a unit type is a folder name in" in _refused(write_formation, text)


def _own_servo(project: Path) -> Path:
    """The project's servo as a unit type of the user's own, ``my_servo``: its unit.yaml."""
    (project / "units" / "servo").rename(project / "units" / "my_servo")
    return project / "units" / "my_servo" / "unit.yaml"


OWN_SNAKE = SNAKE.replace("name: snake", "name: s\nunits_dir: ../units").replace(
    "unit: servo", "unit: my_servo"
)


def test_link_templates_stay_in_the_unit_folder(project, write_formation):
    unit = _own_servo(project)
    unit.write_text(
        unit.read_text().replace("link_template: link.urdf", "link_template: ../hub/link.urdf")
    )
    assert "link_template: must be a file in the unit's folder" in _refused(
        write_formation, OWN_SNAKE
    )
