"""Unit types of the user's own (``units_dir``) add to the shipped ones: both are reachable, a
run copies both, and a name the two define differently is refused naming both files."""

from __future__ import annotations

import shutil
import textwrap
from pathlib import Path

import pytest
from helpers import TINY_TRAINING

from qdsega.cli import main
from qdsega.description import load_formation
from qdsega.description.shipped import UNITS_DIR
from qdsega.errors import FormationError

MIXED = """\
name: mixed
light: {distance_m: 3}
units_dir: ../my_units
units:
  - {name: head, unit: servo}
  - {name: mid, unit: heavy_servo, parent: head, connector: back, axis: yaw, levels_deg: [-20, 20]}
  - {name: tail, unit: servo, parent: mid, connector: back, axis: yaw, levels_deg: [-20, 0, 20]}
"""


@pytest.fixture
def mixed(tmp_path: Path) -> Path:
    """A project with one unit type of its own, ``heavy_servo`` (a servo of 0.3 kg), and a
    formation that uses it beside the shipped ``servo``."""
    own = tmp_path / "my_units" / "heavy_servo"
    shutil.copytree(UNITS_DIR / "servo", own)
    unit = own / "unit.yaml"
    unit.write_text(unit.read_text().replace("mass_kg: 0.15", "mass_kg: 0.3"))
    (tmp_path / "assemblies").mkdir()
    file = tmp_path / "assemblies" / "mixed.yaml"
    file.write_text(MIXED)
    return file


@pytest.mark.slow
def test_own_and_shipped_unit_types_assemble_train_and_evaluate(mixed, tmp_path, capsys):
    formation = load_formation(mixed)
    masses = {u.name: u.unit_type.mass_kg for u in formation.units}
    assert masses == {"head": 0.15, "mid": 0.3, "tail": 0.15}
    assert main(["assemble", str(mixed), "-o", str(tmp_path / "mixed.urdf")]) == 0
    (tmp_path / "tiny.yaml").write_text(TINY_TRAINING)
    run = tmp_path / "run"
    args = ["train", str(mixed), "--sim", "memo", "--preset", "paper-snake", "--generations",
            "1", "--config", str(tmp_path / "tiny.yaml"), "--out", str(run), "--quiet"]  # fmt: skip
    assert main(args) == 0
    copied = sorted(p.name for p in (run / "formation" / "units").iterdir())
    assert copied == ["heavy_servo", "servo"]
    shutil.rmtree(tmp_path / "my_units")  # the run needs its copy only
    assert main(["evaluate", str(run), "--reference-trials", "0"]) == 0
    assert "mixed: learnt policy" in capsys.readouterr().out


def test_a_name_both_define_differently_names_both_files(mixed, tmp_path):
    clash = tmp_path / "my_units" / "servo"
    shutil.copytree(UNITS_DIR / "servo", clash)
    unit = clash / "unit.yaml"
    unit.write_text(unit.read_text().replace("mass_kg: 0.15", "mass_kg: 0.2"))
    with pytest.raises(FormationError) as refused:
        load_formation(mixed)
    message = str(refused.value)
    assert "unit type 'servo' is defined twice" in message
    assert str(clash / "unit.yaml") in message and str(UNITS_DIR / "servo" / "unit.yaml") in message


def test_a_file_for_file_copy_of_a_shipped_type_is_the_same_type(mixed, tmp_path):
    shutil.copytree(UNITS_DIR / "servo", tmp_path / "my_units" / "servo")
    assert load_formation(mixed).root.unit_type.mass_kg == 0.15


def test_an_unknown_type_names_every_folder_searched(mixed):
    mixed.write_text(textwrap.dedent(MIXED).replace("unit: heavy_servo", "unit: gearbox"))
    with pytest.raises(FormationError, match="unknown unit type 'gearbox'") as refused:
        load_formation(mixed)
    assert "my_units/gearbox/unit.yaml or " in str(refused.value)
