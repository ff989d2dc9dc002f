import dataclasses
import io
import json
import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from helpers import SHIPPED_FORMATIONS

from qdsega.baselines import reference_search
from qdsega.baselines.cpg import CPGGait
from qdsega.baselines.reference_search import reference_gait, reference_key
from qdsega.description import Light, load_formation
from qdsega.description.shipped import ASSEMBLIES_DIR
from qdsega.locomotion.env import LocomotionEnv, replay_postures
from qdsega.locomotion.lower_agent import LowerAgentConfig
from qdsega.locomotion.rules import ExactRules
from qdsega.progress import ProgressLine
from qdsega.simulation import PhysicsSettings
from qdsega.task import TaskConfig
from qdsega.training.config import resolve_config

pytestmark = pytest.mark.slow  # end to end: make test-fast leaves it out

SNAKE = load_formation(ASSEMBLIES_DIR / "snake5.yaml")
STEPS = 6
RULES = ExactRules(task=TaskConfig(trial_steps=STEPS))
ONE_GENERATION = 11  # CMA-ES's population for snake5's 13 coordinates
QUICK = ExactRules(task=TaskConfig(trial_steps=2))  # for the cache: any result will do


@pytest.fixture(autouse=True)
def user_cache(tmp_path, monkeypatch):
    """Every test gets an empty user cache and no shipped references."""
    monkeypatch.setenv("QDSEGA_CACHE", str(tmp_path / "cache"))
    monkeypatch.setattr(reference_search, "SHIPPED_DIR", tmp_path / "shipped")
    return tmp_path / "cache" / "references"


@pytest.fixture
def searches(monkeypatch):
    """Counts the searches that run."""
    calls = []
    search = reference_search._search

    def counted(*args):
        calls.append(args)
        return search(*args)

    monkeypatch.setattr(reference_search, "_search", counted)
    return calls


def _replay(formation, postures, task=RULES.task):
    """Distance (m) and failure of a posture sequence in the env learning uses."""
    env = LocomotionEnv(formation=formation, task=task)
    try:
        replay = replay_postures(env, postures)
        return replay.distance_m, replay.failure
    finally:
        env.close()


def test_the_search_beats_a_bad_gait_and_depends_on_the_seed_only(searches):
    result = reference_gait(SNAKE, rules=RULES, budget_trials=2 * ONE_GENERATION, workers=2)
    # Bad gaits: standing still, and a standing wave (every joint in phase) that goes nowhere.
    n = len(SNAKE.joints)
    standing_wave = CPGGait(
        amplitude_rad=(math.radians(20),) * n,
        offset_rad=(0.0,) * n,
        phase_rad=(0.0,) * n,
        period_steps=4,
    )
    rest = np.tile(SNAKE.rest_levels(), (STEPS, 1))
    bad = max(
        _replay(SNAKE, standing_wave.postures(SNAKE, steps=STEPS))[0], _replay(SNAKE, rest)[0]
    )
    distance, failure = _replay(SNAKE, result.postures)
    assert failure is None
    assert distance == pytest.approx(result.distance_m, abs=1e-9)
    assert result.distance_m > bad + 0.02
    assert result.postures.shape == (STEPS, n)
    assert result.evaluations == 2 * ONE_GENERATION
    assert result.budget_steps == 2 * ONE_GENERATION * STEPS
    assert len(result.history_m) == 2
    assert list(result.history_m) == sorted(result.history_m)
    assert result.history_m[-1] == result.distance_m
    # One worker, no cache: the same gait, trial for trial.
    again = reference_gait(
        SNAKE, rules=RULES, budget_trials=2 * ONE_GENERATION, workers=1, cache=False
    )
    assert again.params == result.params and again.history_m == result.history_m
    assert again.file is None
    other = reference_gait(
        SNAKE, rules=RULES, budget_trials=ONE_GENERATION, seed=1, workers=1, cache=False
    )
    assert other.history_m[0] != result.history_m[0]  # another seed, another first generation
    assert len(searches) == 3


def test_a_legged_reference_never_fails():
    quadruped = load_formation(ASSEMBLIES_DIR / "quadruped.yaml")
    result = reference_gait(quadruped, rules=RULES, budget_trials=13, workers=1, cache=False)
    distance, failure = _replay(quadruped, result.postures)
    assert failure is None
    assert distance == pytest.approx(result.distance_m, abs=1e-9)


def test_the_key_changes_with_every_input_and_nothing_else(write_formation, monkeypatch):
    text = (ASSEMBLIES_DIR / "snake5.yaml").read_text(encoding="utf-8")
    base = reference_key(SNAKE, rules=RULES)
    assert len(base) == 64
    assert reference_key(load_formation(write_formation(text, "copy")), rules=RULES) == base
    assert (
        reference_key(SNAKE, rules=RULES, budget_trials=reference_search.DEFAULT_BUDGET_TRIALS)
        == base
    )
    # An open-loop gait earns no reward: the reward's unit and the penalty are not inputs.
    rewarded = TaskConfig(trial_steps=STEPS, distance_unit_m=0.01, penalty=-5.0)
    assert reference_key(SNAKE, rules=dataclasses.replace(RULES, task=rewarded)) == base

    def key(formation=SNAKE, **change):
        search = {k: change.pop(k) for k in ("budget_trials", "seed") if k in change}
        return reference_key(formation, rules=dataclasses.replace(RULES, **change), **search)

    variants = {
        "levels": key(load_formation(write_formation(text.replace("step: 5", "step: 10"), "a"))),
        "friction": key(load_formation(write_formation(text.replace("0.8", "0.7"), "b"))),
        "mass": key(
            load_formation(write_formation(text.replace("unit: servo", "unit: hub", 1), "c"))
        ),
        "light": key(SNAKE.with_light(Light(distance_m=50.0, bearing_rad=0.5))),
        "trial steps": key(task=TaskConfig(trial_steps=STEPS + 1)),
        "step duration": key(lower_agent=LowerAgentConfig(step_duration_s=0.55)),
        "physics": key(physics=PhysicsSettings(solver_iterations=40)),
        "budget": key(budget_trials=100),
        "seed": key(seed=1),
    }
    with monkeypatch.context() as patch:
        patch.setattr(reference_search, "PERIODS", (4, 5))
        variants["periods"] = key()
    with monkeypatch.context() as patch:
        patch.setattr(reference_search, "FORMAT_VERSION", reference_search.FORMAT_VERSION + 1)
        variants["format"] = key()
    assert base not in variants.values()
    assert len(set(variants.values())) == len(variants)


def test_a_cached_result_is_reused_without_simulating(searches, user_cache):
    first = reference_gait(SNAKE, rules=QUICK, budget_trials=ONE_GENERATION, workers=1)
    assert first.file is not None and first.file.parent == user_cache
    stored = json.loads(first.file.read_text(encoding="utf-8"))
    assert stored["key"] == first.key
    assert stored["inputs"]["trial_steps"] == 2
    assert stored["inputs"]["search"]["budget_trials"] == ONE_GENERATION
    assert stored["postures"] == first.postures.tolist()
    second = reference_gait(SNAKE, rules=QUICK, budget_trials=ONE_GENERATION, workers=2)
    assert len(searches) == 1
    for field in dataclasses.fields(first):
        a, b = getattr(first, field.name), getattr(second, field.name)
        assert np.array_equal(a, b) if isinstance(a, np.ndarray) else a == b, field.name


def test_a_shipped_reference_comes_before_the_user_cache(searches, user_cache, tmp_path):
    first = reference_gait(SNAKE, rules=QUICK, budget_trials=ONE_GENERATION, workers=1)
    shipped = tmp_path / "shipped"
    shipped.mkdir()
    (shipped / first.file.name).write_bytes(first.file.read_bytes())
    first.file.unlink()
    found = reference_gait(SNAKE, rules=QUICK, budget_trials=ONE_GENERATION, workers=1)
    assert found.file == shipped / first.file.name
    assert found.params == first.params
    assert len(searches) == 1


@pytest.mark.parametrize(
    "spoil",
    [
        lambda text: text[: len(text) // 2],
        lambda text: text.replace('"postures": [', '"postures": [[0, 0, 0, 0], ', 1),
        lambda text: text.replace('"key": "', '"key": "0', 1),
    ],
    ids=["truncated", "postures not the gait's", "another key"],
)
def test_a_corrupt_cache_file_is_recomputed(searches, capsys, spoil):
    first = reference_gait(SNAKE, rules=QUICK, budget_trials=ONE_GENERATION, workers=1)
    first.file.write_text(spoil(first.file.read_text(encoding="utf-8")), encoding="utf-8")
    capsys.readouterr()
    second = reference_gait(SNAKE, rules=QUICK, budget_trials=ONE_GENERATION, workers=1)
    warning = capsys.readouterr().err
    assert warning.count("\n") == 1 and "corrupt reference" in warning
    assert str(first.file) in warning
    assert len(searches) == 2
    assert second.params == first.params
    reference_gait(SNAKE, rules=QUICK, budget_trials=ONE_GENERATION, workers=1)  # rewritten whole
    assert len(searches) == 2


def test_a_search_shows_trials_of_the_budget_and_the_best_so_far(capsys):
    stream, made = io.StringIO(), []

    def factory(label: str, total: int, *, delay_s: float = 0.0, initial: int = 0) -> ProgressLine:
        made.append((label, total))
        return ProgressLine(label, total, stream=stream, every_s=0.0)  # every iteration

    budget = 2 * ONE_GENERATION + 3  # the search stops at 22 of 25: the last line still shows
    found = reference_gait(SNAKE, rules=QUICK, budget_trials=budget, workers=1, progress=factory)
    assert made == [("reference search", budget)]
    lines = stream.getvalue().splitlines()
    assert [line.split(":")[0] for line in lines] == [
        "reference search 11/25",
        "reference search 22/25",
    ]
    assert lines[-1].startswith(f"reference search 22/25: best {found.distance_m:.3f} m, elapsed ")
    reference_gait(SNAKE, rules=QUICK, budget_trials=budget, workers=1, progress=factory)
    assert len(made) == 1  # cached: no search, no line
    reference_gait(SNAKE, rules=QUICK, budget_trials=budget, workers=1, cache=False)
    assert capsys.readouterr().err == ""  # no factory: silent


def test_bad_settings_are_refused():
    with pytest.raises(ValueError, match="one CMA-ES generation"):
        reference_gait(SNAKE, rules=RULES, budget_trials=ONE_GENERATION - 1)
    with pytest.raises(ValueError, match="workers"):
        reference_gait(SNAKE, rules=RULES, workers=0)


def test_no_completed_trial_is_an_error():
    blocked = LowerAgentConfig(tolerance_rad=1e-9)  # no joint ever reaches its level so closely
    with pytest.raises(ValueError, match="completed"):
        reference_gait(
            SNAKE,
            rules=dataclasses.replace(QUICK, lower_agent=blocked),
            budget_trials=ONE_GENERATION,
            workers=1,
            cache=False,
        )


SHIPPED = reference_search.SHIPPED_DIR  # before the fixture hides it
TOOL = Path(__file__).resolve().parents[2] / "tools" / "reference_search.py"


@pytest.mark.parametrize("name", [file.stem for file in SHIPPED_FORMATIONS])
def test_every_shipped_formation_ships_its_reference_under_the_presets_rules(name):
    """Changing what a search depends on (physics, lower agent, assembler, a formation) makes
    the shipped file stale: re-run ``tools/reference_search.py NAME --ship``."""
    config = resolve_config()
    key = reference_key(
        load_formation(ASSEMBLIES_DIR / f"{name}.yaml"),
        rules=config.rules(),
    )
    assert (SHIPPED / f"{name}-{key[:16]}.json").is_file(), f"stale or missing: {name}"


SNAKE3 = (
    (ASSEMBLIES_DIR / "snake5.yaml")
    .read_text()
    .replace("name: snake5", "name: snake3")
    .replace("repeat: [2, 5]", "repeat: [2, 3]")
)
"""snake5 cut to 3 units, 2 joints: a body the tool searches in a third of snake5's time."""
SNAKE3_GENERATION = 9  # CMA-ES's population for its 7 coordinates


def test_the_tool_searches_then_reads_its_cache(tmp_path):
    body = tmp_path / "snake3.yaml"
    body.write_text(SNAKE3)
    command = [sys.executable, TOOL, body, "--budget-trials", str(SNAKE3_GENERATION)]
    first = subprocess.run([*command, "--workers", "1"], capture_output=True, text=True)
    assert first.returncode == 0, first.stderr
    assert f"search of {SNAKE3_GENERATION} trials ({SNAKE3_GENERATION * 30} steps" in first.stdout
    again = subprocess.run(command, capture_output=True, text=True)
    assert again.stdout.splitlines()[0] == first.stdout.splitlines()[0]  # same wall_s: cached
