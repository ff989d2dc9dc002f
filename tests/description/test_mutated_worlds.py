"""Mutants of every shipped world: each either builds in PyBullet with a snake resting on it,
or is refused in one line that names the file (a start inside an obstacle counts as refused);
each within 5 s. The mutations are the formations' (``helpers.mutants``)."""

import time
from pathlib import Path
from typing import Any

import numpy as np
import pytest
import yaml
from helpers import SHIPPED_WORLDS, mutants

from qdsega.assembly import assemble
from qdsega.description import load_formation, load_world, resolve_formation
from qdsega.errors import WorldError
from qdsega.simulation.bullet import BulletSimulation

pytestmark = pytest.mark.slow  # hundreds of worlds built: make test-fast leaves it out

SECONDS_PER_MUTANT = 5.0
SNAKE = load_formation(resolve_formation("snake5"))
ROBOT = assemble(SNAKE)


def _check_mutant(data: Any, folder: Path) -> str:
    """``built`` or ``refused``; AssertionError if the mutant misbehaves."""
    file = folder / "mutant.yaml"
    file.write_text(yaml.safe_dump(data, sort_keys=False), encoding="utf-8")
    start = time.perf_counter()
    try:
        world = load_world(file)
        with BulletSimulation(robot=ROBOT, world=world) as sim:
            sim.reset(SNAKE.posture_rad(SNAKE.rest_levels()))
            sim.step(24)
            assert np.all(np.isfinite(sim.unit_states()[0])), "NaN in PyBullet"
        outcome = "built"
    except WorldError as exc:
        text = str(exc)
        assert "\n" not in text and text.startswith(f"{file}"), text
        outcome = "refused"
    elapsed = time.perf_counter() - start
    assert elapsed < SECONDS_PER_MUTANT, f"took {elapsed:.1f} s"
    return outcome


@pytest.mark.parametrize("file", SHIPPED_WORLDS, ids=lambda f: f.stem)
def test_every_mutant_builds_with_a_body_resting_on_it_or_is_refused_in_one_line(file, tmp_path):
    data = yaml.safe_load(file.read_text(encoding="utf-8"))
    outcomes = {"built": 0, "refused": 0}
    failures = []
    for label, mutant in mutants(data):
        try:
            outcomes[_check_mutant(mutant, tmp_path)] += 1
        except AssertionError as exc:
            failures.append(f"{label}: {exc}")
    assert not failures, "\n".join(failures)
    print(f"{file.stem}: {sum(outcomes.values())} mutants, {outcomes}")
    assert outcomes["built"] >= 1 and outcomes["refused"] >= 2
