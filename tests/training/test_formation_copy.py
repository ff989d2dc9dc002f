"""A run folder's copy of its formation: the same formation from the copy, its hash, the
warning when the original changes, and refusals."""

from __future__ import annotations

import shutil
import warnings
from pathlib import Path

import pytest
import trimesh

from qdsega.assembly import assemble
from qdsega.description import Formation, load_formation
from qdsega.errors import QdsegaWarning, RunFolderError
from qdsega.training.config import TrainingConfig
from qdsega.training.formation_copy import (
    FormationSnapshot,
    content_hash,
    load_run_formation,
    read_formation_record,
)

SNAKE = Path("assemblies/snake5.yaml")


@pytest.fixture
def meshed(project: Path) -> Path:
    """snake5 on the project's servo, which shows two meshes: one in its folder, one in a
    folder beside ``units/`` (which the loader allows, though the assembler does not yet)."""
    folder = project / "units" / "meshed_servo"  # a unit type of the user's own
    (project / "units" / "servo").rename(folder)
    (folder / "meshes").mkdir()
    (project / "meshes").mkdir()
    trimesh.creation.box(extents=(0.096, 0.05, 0.05)).export(folder / "meshes" / "housing.stl")
    trimesh.creation.cylinder(radius=0.018, height=0.052).export(project / "meshes" / "horn.stl")
    template = folder / "link.urdf"
    text = template.read_text()
    text = text.replace('<box size="0.096 0.05 0.05"/>', '<mesh filename="meshes/housing.stl"/>')
    text = text.replace(
        '<cylinder radius="0.018" length="0.052"/>', '<mesh filename="../../meshes/horn.stl"/>'
    )
    template.write_text(text)
    file = project / "assemblies" / "snake.yaml"
    text = SNAKE.read_text().replace("unit: servo", "unit: meshed_servo")
    file.write_text(text + "units_dir: ../units\n")
    return file


def _copy(formation_file: Path, run: Path) -> None:
    run.mkdir()
    FormationSnapshot.of(load_formation(formation_file)).write(run)


def _model(formation: Formation) -> tuple:
    """Everything of a formation but where its files are."""
    types = [(u.unit_type.link_template, u.unit_type.mass_kg) for u in formation.units]
    return formation.name, formation.light, formation.joints, formation.legs, types


def _load_quietly(run: Path, config: TrainingConfig | None = None):
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        return load_run_formation(run, config or TrainingConfig())


def test_the_copy_holds_every_file_and_loads_as_the_same_formation(meshed, tmp_path):
    run = tmp_path / "run"
    _copy(meshed, run)
    record = read_formation_record(run)
    assert sorted(record.files) == [
        "meshes/horn.stl",
        "snake.yaml",
        "units/meshed_servo/link.urdf",
        "units/meshed_servo/meshes/housing.stl",
        "units/meshed_servo/unit.yaml",
    ]
    assert record.source_file == str(meshed.resolve())
    original, copy = load_formation(meshed), _load_quietly(run)
    assert copy.file == run / "formation" / "snake.yaml"
    assert _model(copy) == _model(original)
    horn = copy.root.unit_type.folder / "../../meshes/horn.stl"
    assert horn.resolve() == run / "formation" / "meshes" / "horn.stl"


def test_the_copy_assembles_to_the_same_robot(tmp_path):
    run = tmp_path / "run"
    _copy(SNAKE, run)
    original, copy = assemble(load_formation(SNAKE)), assemble(_load_quietly(run))
    assert copy.urdf == original.urdf and copy.mass_kg == original.mass_kg


def test_the_hash_is_the_contents_wherever_the_folder_is(meshed, tmp_path):
    run = tmp_path / "run"
    _copy(meshed, run)
    moved = tmp_path / "elsewhere" / "run"
    shutil.copytree(run, moved)
    for folder in ("units", "assemblies", "meshes"):  # the original project is gone
        shutil.rmtree(tmp_path / folder)
    assert read_formation_record(moved).sha256 == read_formation_record(run).sha256
    assert len(read_formation_record(moved).sha256) == 64
    assert _model(_load_quietly(moved)) == _model(_load_quietly(run))
    assert content_hash({"a": "1", "b": "2"}) == content_hash({"b": "2", "a": "1"})
    assert content_hash({"a": "1"}) != content_hash({"a": "2"})


def test_an_edited_original_warns_once_and_the_copy_is_used(meshed, tmp_path):
    run = tmp_path / "run"
    _copy(meshed, run)
    unit = meshed.parent.parent / "units" / "meshed_servo" / "unit.yaml"
    unit.write_text(unit.read_text().replace("mass_kg: 0.15", "mass_kg: 0.5"))
    with pytest.warns(QdsegaWarning) as caught:
        formation = load_run_formation(run, TrainingConfig())
    assert len(caught) == 1
    message = str(caught[0].message)
    assert str(meshed.resolve()) in message and "using the copy" in message
    assert "\n" not in message
    assert formation.root.unit_type.mass_kg == 0.15


def test_the_light_bearing_of_the_configuration_applies_to_the_copy(tmp_path):
    run = tmp_path / "run"
    _copy(SNAKE, run)
    turned = _load_quietly(run, TrainingConfig(light_bearing_deg=90.0))
    assert turned.light.bearing_rad == pytest.approx(1.5707963)


@pytest.mark.parametrize(
    ("damage", "message"),
    [
        (lambda run: (run / "formation.json").unlink(), "no copy of the formation"),
        (lambda run: (run / "formation.json").write_text("{"), "corrupt formation.json"),
        (lambda run: (run / "formation" / "units" / "servo" / "unit.yaml").unlink(), "missing"),
        (
            lambda run: (run / "formation" / "snake5.yaml").write_text("name: other\n"),
            "snake5.yaml differs from its sha256",
        ),
    ],
)
def test_a_damaged_copy_is_refused(tmp_path, damage, message):
    run = tmp_path / "run"
    _copy(SNAKE, run)
    damage(run)
    with pytest.raises(RunFolderError, match=message) as error:
        load_run_formation(run, TrainingConfig())
    assert "\n" not in str(error.value)
