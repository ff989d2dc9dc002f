"""Random valid formations (chains, trees, legged bodies) read, assemble and load in PyBullet.

The formations come from ``qdsega.description.random_formation``: hypothesis draws the seeds
here, and ``tools/random_formations.py`` runs the same generator at scale
(60 of them below; the tool has run 200 with no failure).
"""

import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np
import pytest
import yaml
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from qdsega.assembly import assemble
from qdsega.description import load_formation
from qdsega.description.random_formation import random_formation
from qdsega.simulation.bullet import BulletSimulation

pytestmark = pytest.mark.slow  # end to end: make test-fast leaves it out

TOOL = Path(__file__).resolve().parents[2] / "tools" / "random_formations.py"


def _expected_counts(data: dict) -> tuple[int, int]:
    """(units, joints) of formation data, counted from its entries: repeats and templates;
    a locked joint is no joint."""
    units = joints = 0
    for entry in data["units"]:
        first, last = entry.get("repeat", [1, 1])
        copies = last - first + 1
        if "template" in entry:
            template_units = data["templates"][entry["template"]]["units"]
            units += copies * len(template_units)
            joints += copies * sum(1 for u in template_units if u["unit"] == "servo")
        else:
            units += copies
            working = "parent" in entry and "locked_deg" not in entry
            joints += copies * (entry["unit"] == "servo" and working)
    return units, joints


def test_the_generator_is_deterministic_and_varied():
    first = [random_formation(np.random.default_rng(seed)) for seed in range(40)]
    assert first == [random_formation(np.random.default_rng(seed)) for seed in range(40)]
    entries = [entry for data in first for entry in data["units"]]
    assert any("template" in entry for entry in entries), "legged bodies"
    assert any("repeat" in entry for entry in entries), "repeated entries"
    assert any(entry.get("connector") in ("left", "right") for entry in entries), "trees"
    assert {entry["unit"] for entry in entries if "unit" in entry} == {"servo", "hub"}
    assert any(isinstance(entry.get("axis"), list) for entry in entries), "vector axes"
    assert any(isinstance(entry.get("levels_deg"), dict) for entry in entries), "level ranges"
    assert any("locked_deg" in entry for entry in entries), "broken joints"


@settings(max_examples=25, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.integers(min_value=0, max_value=2**32 - 1))
def test_random_formations_assemble_and_load_in_pybullet(seed):
    data = random_formation(np.random.default_rng(seed))
    with tempfile.TemporaryDirectory() as folder:
        file = Path(folder) / "random.yaml"
        file.write_text(yaml.safe_dump(data, sort_keys=False))
        formation = load_formation(file)
        robot = assemble(formation)
    assert (len(formation.units), len(formation.joints)) == _expected_counts(data)
    with BulletSimulation(robot=robot) as sim:
        assert sim.client.getNumJoints(sim.body_id) == len(formation.units) - 1
        sim.reset(formation.posture_rad(formation.rest_levels()))
        sim.step(24)
        assert np.all(np.isfinite(sim.unit_states()[0]))
        assert np.all(np.isfinite(sim.joint_positions()))


def test_sixty_random_formations_rest_in_pybullet():
    result = subprocess.run(
        [sys.executable, TOOL, "60", "--seed", "0"],
        capture_output=True,
        text=True,
        timeout=300,
        check=False,
    )
    assert result.returncode == 0, result.stderr
    assert result.stdout.startswith("60 random formations (") and ", 0 failures," in result.stdout
