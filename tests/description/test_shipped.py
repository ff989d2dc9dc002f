"""Shipped formations by name, as every command takes them."""

import pytest

from qdsega.cli import main
from qdsega.description import resolve_formation, shipped_formation_names
from qdsega.description.shipped import ASSEMBLIES_DIR
from qdsega.errors import FormationError


def test_every_shipped_formation_has_a_name():
    assert shipped_formation_names() == sorted(f.stem for f in ASSEMBLIES_DIR.glob("*.yaml"))
    assert {"snake5", "legged12"} <= set(shipped_formation_names())


def test_a_bare_name_is_the_shipped_formation(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    assert resolve_formation("snake5") == ASSEMBLIES_DIR / "snake5.yaml"


def test_a_file_of_that_name_comes_first(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "snake5").write_text("name: mine\n")
    assert resolve_formation("snake5").resolve() == tmp_path / "snake5"


@pytest.mark.parametrize("argument", ["snake5.yaml", "robots/snake5", "/x/snake5", "snake5.yml"])
def test_anything_with_a_folder_or_a_suffix_is_a_path(tmp_path, monkeypatch, argument):
    monkeypatch.chdir(tmp_path)
    assert str(resolve_formation(argument)) == argument


def test_an_unknown_name_lists_the_shipped_ones(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    with pytest.raises(FormationError) as info:
        resolve_formation("snak5")
    assert str(info.value) == (
        "snak5: no such file, nor a shipped formation (shipped: "
        + ", ".join(shipped_formation_names())
        + ")"
    )


def test_assemble_takes_names(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    assert main(["assemble", "snake5", "quadruped"]) == 0
    assert (tmp_path / "snake5.urdf").is_file() and (tmp_path / "quadruped.urdf").is_file()
    assert main(["assemble", "snak5"]) == 2
    err = capsys.readouterr().err
    assert err.startswith("qdsega assemble: error: snak5: no such file") and err.count("\n") == 1
