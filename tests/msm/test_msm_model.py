"""The MSM's equations (7)-(16), its failure rule and its construction from formations."""

from __future__ import annotations

import math

import numpy as np
import pytest

from qdsega.description import load_formation
from qdsega.description.shipped import ASSEMBLIES_DIR
from qdsega.errors import FormationError
from qdsega.msm import LegLayout, MinimalSimulationModel, MSMParameters, side_force
from qdsega.task import move_pose


def posture(legs: LegLayout, states: list[int]) -> np.ndarray:
    return legs.posture(np.array(states), base=np.zeros(legs.n_joints, dtype=np.int64))


def test_leg_states_follow_the_paper_numbering(layout):
    legs = layout(2)
    p = posture(legs, [1, 2, 3, 4])
    assert p.tolist() == [0, 0, 1, 0, 0, 1, 1, 1]
    assert legs.states(p).tolist() == [1, 2, 3, 4]


@pytest.mark.parametrize(
    ("drive", "resistance", "expected"),
    [
        (1.0, 1.0, 0.0),  # |f_drv| <= f_res: stuck
        (-1.0, 1.5, 0.0),
        (3.0, 1.0, 2.0),  # f_drv > f_res
        (-3.0, 1.0, -2.0),  # f_drv < -f_res
        (0.0, 0.0, 0.0),
    ],
)
def test_eq9_each_branch(drive, resistance, expected):
    assert side_force(drive, resistance) == expected


def test_eqs_7_to_13_on_a_stroke(layout):
    legs = layout(3)
    model = MinimalSimulationModel(legs=legs, params=MSMParameters(u=1.0, v=0.5, c_u=0.1))
    start = posture(legs, [1, 1, 1, 1, 1, 1])
    # Left: two legs stroke (1->2), one stays (1->1): f_drv 2, f_res 0.5 -> F^l 1.5.
    # Right: one leg strokes, two stay: f_drv 1 = f_res 1 -> F^r 0 (eq. 9, first case).
    target = posture(legs, [2, 2, 1, 2, 1, 1])
    t = model.transitions(start[None], target[None])
    assert t.dx[0, 0] == pytest.approx(0.1 * 1.5)
    assert t.dtheta[0, 0] == pytest.approx(0.05 * (0.0 - 1.5))
    assert t.dy[0, 0] == 0.0 and not t.failed[0, 0]


def test_one_side_striding_turns_the_robot_toward_the_other_side(layout):
    legs = layout(2)
    model = MinimalSimulationModel(legs=legs, params=MSMParameters())
    a = posture(legs, [1, 1, 1, 1])
    b = posture(legs, [3, 1, 2, 2])  # left: one lifts, one stands (F^l 0); right strokes
    t = model.transitions(a[None], b[None])
    assert t.dtheta[0, 0] > 0  # more push on the right: counter-clockwise, toward the left
    pose = move_pose(0.0, 0.0, 0.0, t.dx[0, 0], t.dy[0, 0], t.dtheta[0, 0])
    assert pose[0] == pytest.approx(t.dx[0, 0]) and pose[1] == 0.0  # eqs. 14-15 use theta(t)
    pose = move_pose(*pose, 1.0, 0.0, 0.0)
    assert pose[1] == pytest.approx(math.sin(t.dtheta[0, 0]))


def test_the_robot_falls_when_a_side_has_too_few_legs_down(layout):
    legs = layout(3)
    model = MinimalSimulationModel(legs=legs, params=MSMParameters(min_down_per_side=1))
    assert model.falls(posture(legs, [3, 4, 3, 1, 2, 1])[None])[0]  # left side all up
    assert not model.falls(posture(legs, [3, 4, 1, 3, 3, 2])[None])[0]
    all_up = posture(legs, [3, 4, 3, 4, 3, 4])
    assert model.falls(all_up[None])[0]
    t = model.transitions(posture(legs, [1] * 6)[None], all_up[None])
    assert t.failed[0, 0] and t.dx[0, 0] == 0.0
    strict = MinimalSimulationModel(legs=legs, params=MSMParameters(min_down_per_side=2))
    assert strict.falls(posture(legs, [3, 4, 1, 1, 1, 1])[None])[0]


@pytest.mark.parametrize(("name", "per_side"), [("legged12", 6), ("hexapod", 3), ("quadruped", 2)])
def test_built_from_any_legged_formation(name, per_side):
    formation = load_formation(ASSEMBLIES_DIR / f"{name}.yaml")
    legs = LegLayout.from_formation(formation)
    assert legs.legs_per_side() == (per_side, per_side)
    model = MinimalSimulationModel(legs=legs, params=MSMParameters())
    assert model.legs.states(model.start_posture()).tolist() == [2] * 2 * per_side


def test_a_snake_is_refused():
    with pytest.raises(FormationError, match="legged formation"):
        LegLayout.from_formation(load_formation(ASSEMBLIES_DIR / "snake5.yaml"))


def test_bad_parameters_are_refused_early(layout):
    with pytest.raises(ValueError, match="start_state"):
        MSMParameters(start_state=5)
    with pytest.raises(ValueError, match="never stand"):
        MinimalSimulationModel(legs=layout(1), params=MSMParameters(min_down_per_side=2))
    with pytest.raises(ValueError, match="falls"):
        MinimalSimulationModel(legs=layout(1), params=MSMParameters(start_state=3))
