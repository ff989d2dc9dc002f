"""The run folder's lock: one holder at a time, and a dead holder's file does not block."""

from __future__ import annotations

import subprocess
import sys

import pytest

from qdsega.errors import RunFolderError
from qdsega.training.run_folder import RunFolder
from qdsega.training.run_lock import run_lock


def test_a_second_holder_is_refused_until_the_first_lets_go(tmp_path):
    with run_lock(tmp_path):
        assert (tmp_path / RunFolder.LOCK).read_text().strip().isdigit()
        with (
            pytest.raises(RunFolderError, match="another qdsega train") as refused,
            run_lock(tmp_path),
        ):
            pass
        assert "\n" not in str(refused.value)
    with run_lock(tmp_path):  # released
        pass


def test_a_lock_file_left_by_a_dead_process_does_not_block(tmp_path):
    dead = subprocess.run([sys.executable, "-c", "import os; print(os.getpid())"],
                          capture_output=True, text=True, check=True).stdout  # fmt: skip
    (tmp_path / RunFolder.LOCK).write_text(dead)
    with run_lock(tmp_path):
        assert (tmp_path / RunFolder.LOCK).read_text() != dead
