"""A file replaced atomically is either the old one or the new one, never a mix or a leftover."""

from __future__ import annotations

import pytest

from qdsega.atomic import replaced_atomically


def test_a_finished_write_replaces_the_file(tmp_path):
    target = tmp_path / "metrics.csv"
    target.write_text("old")
    with replaced_atomically(target) as partial:
        assert partial.parent == tmp_path and partial.suffix == ".csv" and partial != target
        partial.write_text("new")
        assert target.read_text() == "old"
    assert target.read_text() == "new"
    assert [p.name for p in tmp_path.iterdir()] == ["metrics.csv"]


def test_an_interrupted_write_keeps_the_old_file_and_leaves_nothing(tmp_path):
    target = tmp_path / "checkpoint.npz"
    target.write_text("old")
    with pytest.raises(KeyboardInterrupt), replaced_atomically(target) as partial:
        partial.write_text("half")
        raise KeyboardInterrupt
    assert target.read_text() == "old"
    assert [p.name for p in tmp_path.iterdir()] == ["checkpoint.npz"]
