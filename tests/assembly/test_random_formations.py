"""Property test: random valid formations (chains and trees) assemble and load in PyBullet."""

import tempfile
from pathlib import Path

import numpy as np
import yaml
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from qdsega import UNITS_DIR
from qdsega.assembly import assemble
from qdsega.description import load_formation
from qdsega.simulation.bullet import BulletSimulation

CONNECTORS = ("back", "left", "right")  # both shipped unit types have these


@st.composite
def formations(draw: st.DrawFn) -> dict:
    """A formation as YAML data: a random tree of servo and hub units."""
    count = draw(st.integers(min_value=1, max_value=12))
    chain = draw(st.booleans())
    units = [{"name": "n0", "unit": draw(st.sampled_from(["servo", "hub"]))}]
    free = {"n0": list(CONNECTORS)}
    for i in range(1, count):
        candidates = [name for name, slots in free.items() if slots]
        parent = units[-1]["name"] if chain else draw(st.sampled_from(candidates))
        if not free[parent]:
            break
        connector = "back" if chain else draw(st.sampled_from(free[parent]))
        free[parent].remove(connector)
        unit = {
            "name": f"n{i}",
            "unit": draw(st.sampled_from(["servo", "hub"])),
            "parent": parent,
            "connector": connector,
        }
        if unit["unit"] == "servo":
            unit["axis"] = draw(st.sampled_from(["yaw", "pitch", "roll", [1, 1, 0]]))
            degrees = draw(st.lists(st.integers(-90, 90), min_size=1, max_size=5, unique=True))
            unit["levels_deg"] = degrees
        units.append(unit)
        free[unit["name"]] = list(CONNECTORS)
    return {"name": "random", "light": {"distance_m": 5.0}, "units": units}


@settings(max_examples=25, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(formations())
def test_random_formations_assemble_and_load_in_pybullet(data):
    with tempfile.TemporaryDirectory() as folder:
        file = Path(folder) / "random.yaml"
        file.write_text(yaml.safe_dump(data, sort_keys=False))
        formation = load_formation(file, units_dir=UNITS_DIR)
        robot = assemble(formation)
    assert len(formation.units) == len(data["units"])
    assert len(formation.joints) == sum(
        1 for u in data["units"] if u["unit"] == "servo" and "parent" in u
    )
    with BulletSimulation(robot=robot) as sim:
        assert sim.client.getNumJoints(sim.body_id) == len(formation.units) - 1
        sim.reset(np.zeros(len(formation.joints)))
        sim.step(24)
        assert np.all(np.isfinite(sim.unit_states()[0]))
        assert np.all(np.isfinite(sim.joint_positions()))
