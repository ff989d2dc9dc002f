"""The interpreter `make` builds .venv with: python3.11 first, else the newest supported one
with a note that pybullet is then built from source, else one line that says what to install."""

from __future__ import annotations

import os
import shutil
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
SCRIPT = ROOT / "tools" / "pick_python.sh"


def _fake_pythons(folder: Path, usable: dict[str, str | None]) -> dict[str, str]:
    """Executables named like interpreters: ``usable[name]`` is the version they report, or
    None for one that fails the check (too old, or without venv)."""
    folder.mkdir(exist_ok=True)
    for name, version in usable.items():
        body = f'case "$2" in *print*) echo {version};; *) exit 0;; esac' if version else "exit 1"
        path = folder / name
        path.write_text(f"#!/bin/sh\n{body}\n")
        path.chmod(0o755)
    return {"PATH": str(folder)}


def _pick(env: dict[str, str]) -> subprocess.CompletedProcess[str]:
    return subprocess.run(["/bin/sh", str(SCRIPT)], env=env, capture_output=True, text=True)


def test_python311_comes_first_without_a_note(tmp_path):
    env = _fake_pythons(tmp_path, {"python3.11": "3.11", "python3.13": "3.13", "python3": "3.13"})
    picked = _pick(env)
    assert (picked.returncode, picked.stdout, picked.stderr) == (0, "python3.11\n", "")


def test_without_python311_the_newest_supported_is_picked_with_a_note(tmp_path):
    env = _fake_pythons(tmp_path, {"python3.12": "3.12", "python3.13": "3.13"})
    picked = _pick(env)
    assert (picked.returncode, picked.stdout) == (0, "python3.13\n")
    assert picked.stderr.count("\n") == 1 and "C++ compiler" in picked.stderr


def test_an_unusable_interpreter_is_passed_over(tmp_path):
    env = _fake_pythons(tmp_path, {"python3.11": None, "python3.12": "3.12"})
    assert _pick(env).stdout == "python3.12\n"


def test_a_given_python_is_the_only_candidate(tmp_path):
    env = _fake_pythons(tmp_path, {"python3.11": "3.11", "python3.12": "3.12"})
    assert _pick({**env, "PYTHON": "python3.12"}).stdout == "python3.12\n"
    refused = _pick({**env, "PYTHON": "python3.9"})
    assert refused.returncode == 1 and "python3.9" in refused.stderr


@pytest.mark.skipif(shutil.which("make") is None, reason="needs make")
def test_make_demo_without_a_usable_python_stops_saying_what_to_install(tmp_path):
    env = _fake_pythons(tmp_path / "bin", {"python3": None})
    venv = tmp_path / "venv"
    made = subprocess.run(
        [shutil.which("make"), "-C", str(ROOT), f"VENV={venv}", "demo"],
        env={**env, "HOME": os.environ.get("HOME", "/")},
        capture_output=True,
        text=True,
    )
    assert made.returncode != 0 and not venv.exists()
    ours = [line for line in made.stderr.splitlines() if not line.startswith("make")]
    assert len(ours) == 1 and "python3.11-venv" in ours[0]
