"""Mutants of every shipped formation: each either assembles and loads in PyBullet, or
``qdsega assemble`` refuses it (status 2, one line on stderr, no file); each within 5 s.

A mutant changes one thing: a scalar becomes negative, huge (a float, then an integer of 400
digits), NaN or nonsense text; a mapping loses one key or gains an unknown one; a list loses
one item. The CLI runs in-process so that the corpus takes seconds, not minutes.
"""

import time
from typing import Any

import numpy as np
import pytest
import yaml
from helpers import SHIPPED_FORMATIONS, mutants

from qdsega.assembly import assemble
from qdsega.cli import main
from qdsega.description import load_formation
from qdsega.simulation.bullet import BulletSimulation

pytestmark = pytest.mark.slow  # end to end: make test-fast leaves it out

SECONDS_PER_MUTANT = 5.0
SAME_KEYS_AS = {
    "hexapod": "quadruped",
    "hexapod_lost_leg": "quadruped",
    "legged12": "quadruped",
    "quadruped_tripod": "quadruped",
    "snake6": "snake5",
}
"""Bodies written with the same keys as another (the same paths in the YAML, other numbers of
legs or units): their mutants change the same things, so they are left out (the locked leg's
file and snake10's have keys of their own and stay)."""


def _check_mutant(data: Any, folder: Any, capfd: pytest.CaptureFixture[str]) -> str:
    """``assembled`` or ``refused``; AssertionError if the mutant misbehaves."""
    file = folder / "mutant.yaml"
    file.write_text(yaml.safe_dump(data, sort_keys=False), encoding="utf-8")
    out = folder / "out" / "mutant.urdf"
    start = time.perf_counter()
    code = main(["assemble", str(file), "-o", str(out)])
    err = capfd.readouterr().err
    if code == 0:
        assert out.is_file(), "status 0 but no URDF"
        out.unlink()
        formation = load_formation(file)
        with BulletSimulation(robot=assemble(formation)) as sim:
            sim.reset(formation.posture_rad(formation.rest_levels()))
            sim.step(24)
            assert np.all(np.isfinite(sim.unit_states()[0])), "NaN in PyBullet"
    else:
        assert code == 2, f"status {code}: {err}"
        assert len(err.splitlines()) == 1 and err.startswith("qdsega assemble: error: "), err
        assert not out.parent.exists() or not any(out.parent.iterdir()), "left files"
    elapsed = time.perf_counter() - start
    assert elapsed < SECONDS_PER_MUTANT, f"took {elapsed:.1f} s"
    return "assembled" if code == 0 else "refused"


@pytest.mark.parametrize(
    "file", [f for f in SHIPPED_FORMATIONS if f.stem not in SAME_KEYS_AS], ids=lambda f: f.stem
)
def test_every_mutant_assembles_and_loads_or_is_refused_in_one_line(file, tmp_path, capfd):
    data = yaml.safe_load(file.read_text(encoding="utf-8"))
    outcomes = {"assembled": 0, "refused": 0}
    failures = []
    for label, mutant in mutants(data):
        try:
            outcomes[_check_mutant(mutant, tmp_path, capfd)] += 1
        except AssertionError as exc:
            failures.append(f"{label}: {exc}")
    assert not failures, "\n".join(failures)
    print(f"{file.stem}: {sum(outcomes.values())} mutants, {outcomes}")
    assert outcomes["assembled"] >= 5 and outcomes["refused"] >= 100


def _key_paths(data: Any, path: tuple[str, ...] = ()) -> set[tuple[str, ...]]:
    if isinstance(data, dict):
        return set().union(*({(*path, k)} | _key_paths(v, (*path, k)) for k, v in data.items()))
    if isinstance(data, list):
        return set().union(set(), *(_key_paths(v, (*path, "[]")) for v in data))
    return set()


@pytest.mark.parametrize(("body", "like"), SAME_KEYS_AS.items())
def test_a_body_left_out_has_the_keys_of_the_one_it_is_like(body, like):
    files = {f.stem: f for f in SHIPPED_FORMATIONS}
    keys = [_key_paths(yaml.safe_load(files[name].read_text())) for name in (body, like)]
    assert keys[0] == keys[1]
