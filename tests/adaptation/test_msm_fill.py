"""Filling an archive in the MSM: the commanded duty factor by hand, a gait's MSM distance by
hand and against the step-by-step table walk, and a fill that keeps exactly what it measured."""

import math

import numpy as np
import pytest

from qdsega.adaptation.archive import Archive, cvt_centroids
from qdsega.adaptation.fills import default_fill
from qdsega.adaptation.msm_fill import commanded_duty, fill_in_msm, msm_distance
from qdsega.agent.policy import SequencePolicy, rollout
from qdsega.agent.space import ExplorationSpace
from qdsega.agent.table_model import TableModel
from qdsega.description import load_formation, resolve_formation
from qdsega.errors import FormationError
from qdsega.msm import LegLayout, MinimalSimulationModel, MSMParameters
from qdsega.task import Task, TaskConfig

QUADRUPED = load_formation(resolve_formation("quadruped"))
LEGS = LegLayout.from_formation(QUADRUPED)  # L1, L2 left; R1, R2 right
MODEL = MinimalSimulationModel(legs=LEGS, params=MSMParameters())


def _posture(first: int, others: int) -> np.ndarray:
    """The first leg (L1) in state ``first``, every other leg in ``others`` (states 1..4)."""
    states = [first] + [others] * (LEGS.n_legs - 1)
    return LEGS.posture(np.array(states), base=np.zeros(LEGS.n_joints, dtype=np.int64))


# L1 lifts, swings forward, lands and strokes back; the other legs stand still, back and down.
STROKE = np.array([_posture(4, 2), _posture(3, 2), _posture(1, 2), _posture(2, 2)])


def test_the_commanded_duty_factor_is_each_legs_share_of_postures_down():
    assert LEGS.names == ("L1", "L2", "R1", "R2")
    assert commanded_duty(LEGS, STROKE).tolist() == [0.5, 1.0, 1.0, 1.0]


def test_a_gaits_msm_distance_by_hand():
    # Only the fourth step moves: L1's stroke (u = 1) less L2 standing (v = 0.5) leaves the
    # left side 0.5; the right side's two standing legs exert nothing: F = 0.5, M = -0.5, so
    # dx = 0.02 * 0.5 = 0.01 m and dtheta = 0.05 * -0.5 = -0.025 rad.
    light = QUADRUPED.light.position_m
    assert light == pytest.approx((50.0, 0.0))
    one = Task(config=TaskConfig(trial_steps=4), light_xy=light)
    assert msm_distance(MODEL, one, STROKE) == pytest.approx(0.01)
    two = Task(config=TaskConfig(trial_steps=8), light_xy=light)
    x, y = 0.01 + 0.01 * math.cos(-0.025), 0.01 * math.sin(-0.025)
    assert msm_distance(MODEL, two, STROKE) == pytest.approx(50.0 - math.hypot(50.0 - x, y))
    falls = STROKE.copy()
    falls[1] = _posture(3, 4)  # every leg up: the MSM's robot falls
    assert math.isnan(msm_distance(MODEL, two, falls))


def test_a_gaits_msm_distance_is_the_table_walks():
    task = Task(config=TaskConfig(), light_xy=QUADRUPED.light.position_m)
    rng = np.random.default_rng(4)
    for _ in range(5):
        cycle = LEGS.posture(rng.integers(1, 3, LEGS.n_legs), base=np.zeros(8, dtype=np.int64))
        cycle = np.vstack([cycle, STROKE[rng.integers(0, 4)], STROKE[3]])
        space = ExplorationSpace.from_population(cycle, MODEL.start_posture())
        table = MODEL.transitions(space.postures, space.actions)
        world = TableModel(space=space, table=table, task=task)
        policy = SequencePolicy(commands=cycle, space=space)
        walked = rollout(policy, world, steps=task.trial_steps)
        expected = float("nan") if walked.failed else walked.distance_m
        assert msm_distance(MODEL, task, cycle) == pytest.approx(expected, nan_ok=True)


def _fill(evaluations: int, seed: int) -> Archive:
    archive = Archive.empty(cvt_centroids(4, 32, np.random.default_rng(0)), max_cycle=4,
                            n_joints=LEGS.n_joints)  # fmt: skip
    fill_in_msm(QUADRUPED, archive, task=TaskConfig(), evaluations=evaluations, initial=200,
                max_cycle=4, rng=np.random.default_rng(seed))  # fmt: skip
    return archive


def test_a_fill_keeps_gaits_at_their_msm_distance_in_their_cells_and_repeats():
    archive = _fill(3000, seed=1)
    task = Task(config=TaskConfig(), light_xy=QUADRUPED.light.position_m)
    assert len(archive.filled) > 8
    for cell in archive.filled:
        gait = archive.gait(int(cell))
        assert archive.fitness[cell] == pytest.approx(msm_distance(MODEL, task, gait))
        assert np.array_equal(archive.descriptors[cell], commanded_duty(LEGS, gait))
        assert archive.cell_of(commanded_duty(LEGS, gait)) == cell
    again = _fill(3000, seed=1)
    for name, value in archive.state().items():
        assert np.array_equal(value, again.state()[name], equal_nan=True), name


def test_a_body_without_legs_on_both_sides_is_refused_and_filled_in_exact_physics_instead():
    snake = load_formation(resolve_formation("snake5"))
    assert default_fill(snake) == "pybullet" and default_fill(QUADRUPED) == "msm"
    archive = Archive.empty(np.full((4, 2), 0.5), max_cycle=4, n_joints=len(snake.joints))
    with pytest.raises(FormationError, match="needs a legged formation"):
        fill_in_msm(snake, archive, task=TaskConfig(), evaluations=10, initial=5, max_cycle=4,
                    rng=np.random.default_rng(0))  # fmt: skip
