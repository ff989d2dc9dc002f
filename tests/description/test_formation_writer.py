"""A formation written back as YAML reads into the same formation: every shipped one, a body
with a locked leg, a unit's own friction and a folder of the user's own unit types."""

from __future__ import annotations

import shutil
from dataclasses import replace
from pathlib import Path

import pytest
from helpers import SHIPPED_FORMATIONS

from qdsega.description import Formation, load_formation
from qdsega.description.formation_writer import formation_yaml
from qdsega.description.shipped import UNITS_DIR


def comparable(formation: Formation) -> Formation:
    """The formation without where it was read from (file and lines)."""
    units = tuple(replace(u, line=None) for u in formation.units)
    return replace(formation, file=Path("-"), units=units)


def round_trip(formation: Formation, file: Path) -> Formation:
    file.write_text(formation_yaml(formation, file, comment="written back"), encoding="utf-8")
    return load_formation(file)


@pytest.mark.parametrize("file", SHIPPED_FORMATIONS, ids=lambda p: p.stem)
def test_every_shipped_formation_reads_back_the_same(file: Path, tmp_path: Path):
    formation = load_formation(file)
    assert comparable(round_trip(formation, tmp_path / file.name)) == comparable(formation)


def test_a_unit_of_its_own_friction_and_a_comment(tmp_path: Path):
    formation = load_formation(SHIPPED_FORMATIONS[0])
    units = list(formation.units)
    units[1] = replace(units[1], friction=replace(units[1].friction, lateral=0.3))
    changed = replace(formation, units=tuple(units))
    text = formation_yaml(changed, tmp_path / "x.yaml", comment="two\nlines")
    assert text.startswith("# two\n# lines\n")
    assert comparable(round_trip(changed, tmp_path / "x.yaml")) == comparable(changed)


def test_unit_types_of_ones_own_are_found_from_where_the_file_is_written(tmp_path: Path):
    own = tmp_path / "project" / "my_units"
    shutil.copytree(UNITS_DIR / "servo", own / "heavy_servo")
    source = tmp_path / "project" / "body.yaml"
    source.write_text(
        "name: body\nlight: {distance_m: 5}\nunits_dir: my_units\nunits:\n"
        "  - {name: a, unit: servo}\n"
        "  - {name: b, unit: heavy_servo, parent: a, connector: back, axis: yaw,"
        " levels_deg: [-10, 0, 10]}\n"
    )
    formation = load_formation(source)
    elsewhere = tmp_path / "out" / "deep" / "body.yaml"
    elsewhere.parent.mkdir(parents=True)
    assert "units_dir: ../../project/my_units" in formation_yaml(formation, elsewhere)
    assert comparable(round_trip(formation, elsewhere)) == comparable(formation)
