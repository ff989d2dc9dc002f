"""The memo-speed experiments measure what they say, and refuse what they cannot measure."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

pytestmark = pytest.mark.slow  # end to end: make test-fast leaves it out

EXPERIMENT = Path(__file__).resolve().parents[2] / "experiments" / "memo_speed"


def test_the_mirror_check_tool_measures_a_legged_body_and_refuses_a_snake():
    tool = EXPERIMENT / "memo_mirror.py"
    run = [sys.executable, tool]
    result = subprocess.run([*run, "quadruped", "--postures", "3"], capture_output=True, text=True)
    assert result.returncode == 0, result.stderr
    assert result.stdout.startswith("quadruped: 18 transitions measured")
    assert "| dx (m) |" in result.stdout
    refused = subprocess.run([*run, "snake5"], capture_output=True, text=True)
    assert refused.returncode == 1 and "no left-right mirror" in refused.stderr


def test_the_physics_curve_tool_prints_a_row_per_setting():
    tool = EXPERIMENT / "physics_curve.py"
    run = [sys.executable, tool, "quadruped", "--postures", "2", "--settings", "240:50,120:10"]
    result = subprocess.run(run, capture_output=True, text=True)
    assert result.returncode == 0, result.stderr
    rows = [line for line in result.stdout.splitlines() if line[2:3].isdigit()]
    assert [row.split(" |")[0] for row in rows] == ["| 240 : 50", "| 120 : 10"]
    assert rows[0].split("|")[3].strip() == "100.0%"  # the reference agrees with itself
    bad = subprocess.run([*run[:2], "--settings", "fast"], capture_output=True, text=True)
    assert bad.returncode == 1 and "not HZ:ITERATIONS" in bad.stderr
    zero = subprocess.run([*run[:2], "--settings", "0:50"], capture_output=True, text=True)
    assert zero.returncode == 1 and zero.stderr.strip().splitlines() == [
        "--settings: '0:50' needs HZ > 0 and ITERATIONS >= 1"
    ]
