"""The optimum (DP over leg-state counts) against exhaustive search, turns included."""

from __future__ import annotations

import math

import numpy as np
import pytest

from qdsega.msm import MinimalSimulationModel, MSMParameters, msm_optimum

LIGHT = (50.0, 0.0)


def brute_force(model: MinimalSimulationModel, steps: int) -> float:
    """Largest distance toward the light over every posture sequence of ``steps`` commands.

    Exhaustive: every posture is tried after every reachable (posture, pose); states equal in
    posture and pose (exact floats) are merged, which loses nothing. A fall ends the sequence
    with the distance it had.
    """
    n = model.n_joints
    postures = np.array(np.meshgrid(*[[0, 1]] * n, indexing="ij")).reshape(n, -1).T
    start = model.start_posture()
    index = int(np.flatnonzero(np.all(postures == start, axis=1))[0])
    t = model.transitions(postures, postures)
    d0 = math.hypot(*LIGHT)
    frontier = np.array([[index, 0.0, 0.0, 0.0]])
    best = 0.0
    for _ in range(steps):
        i = frontier[:, 0].astype(int)
        x, y, th = (frontier[:, k][:, None] for k in (1, 2, 3))
        ok = ~t.failed[i]
        c, s = np.cos(th), np.sin(th)
        nx = x + t.dx[i] * c - t.dy[i] * s
        ny = y + t.dx[i] * s + t.dy[i] * c
        nth = th + t.dtheta[i]
        j = np.broadcast_to(np.arange(len(postures)), ok.shape)
        rows = np.stack([j[ok], nx[ok], ny[ok], nth[ok]], axis=1)
        frontier = np.unique(rows, axis=0)
        d = np.hypot(LIGHT[0] - frontier[:, 1], LIGHT[1] - frontier[:, 2])
        best = max(best, float(d0 - d.min()))
    return best


@pytest.mark.parametrize(
    ("per_side", "steps", "params"),
    [
        (1, 6, MSMParameters(min_down_per_side=0, c_theta=0.0)),
        (1, 6, MSMParameters(min_down_per_side=1, c_theta=0.0)),
        (1, 5, MSMParameters(min_down_per_side=0, start_state=2, v=1.0, c_theta=0.0)),
        (2, 5, MSMParameters(min_down_per_side=1, c_theta=0.0)),
        (2, 4, MSMParameters(min_down_per_side=0, v=0.25, c_theta=0.0)),
        (2, 4, MSMParameters(min_down_per_side=2, start_state=2, c_theta=0.0)),
    ],
)
def test_dp_equals_brute_force_on_small_bodies(layout, per_side, steps, params):
    model = MinimalSimulationModel(legs=layout(per_side), params=params)
    optimum = msm_optimum(model, steps=steps, light_xy=LIGHT)
    assert optimum.proven
    assert optimum.distance_m == pytest.approx(brute_force(model, steps), abs=1e-12)


@pytest.mark.parametrize("min_down", [0, 1])
def test_turning_adds_at_most_a_second_order_wiggle(layout, min_down):
    """With turns, a stroke at one heading and a back-stroke at another gain c_u (1 - cos):
    exhaustive search finds that much more than the straight optimum, no more."""
    model = MinimalSimulationModel(legs=layout(1), params=MSMParameters(min_down_per_side=min_down))
    optimum = msm_optimum(model, steps=6, light_xy=LIGHT)
    searched = brute_force(model, 6)
    assert optimum.distance_m <= searched + 1e-12
    assert searched - optimum.distance_m <= 1e-4  # m; the straight optimum is 0.04-0.08 m


def test_witness_is_a_valid_sequence_from_the_start_posture(layout):
    model = MinimalSimulationModel(legs=layout(3), params=MSMParameters())
    optimum = msm_optimum(model, steps=12, light_xy=LIGHT)
    assert optimum.postures.shape == (13, model.n_joints)
    assert np.array_equal(optimum.postures[0], model.start_posture())
    assert not model.falls(optimum.postures[1:]).any()
    # A leg strokes at most once every 3 steps, plus once at the start (state 1): per side
    # at most 3 + 12 / 3 * 3 strokes of force u.
    assert optimum.distance_m <= model.params.c_u * 2 * (3 + 12) + 1e-12


def test_light_off_axis_is_not_claimed_exact(layout):
    model = MinimalSimulationModel(legs=layout(1), params=MSMParameters())
    # The light as training passes it (a NumPy array): exact stays a plain bool, which
    # summary.json can hold (np.bool_ broke the turn run of tools/reproduce_msm.py).
    optimum = msm_optimum(model, steps=4, light_xy=np.array([25.0, 43.3]))
    assert optimum.proven is False
    assert optimum.bound_m >= optimum.distance_m
