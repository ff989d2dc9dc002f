"""The optimum of the MSM task: the farthest one trial can get toward the light.

Method: dynamic programming over leg-state *counts*. Under eqs. (7)-(9) the legs of one side
are interchangeable, so a side's state is how many of its legs are in each of the 4 states
(84 states for 6 legs), and one step is a 4x4 matrix ``n_ij`` of how many legs go from ``i`` to
``j`` (its rows sum to the current counts, its columns to the next ones; the next counts must
keep ``min_down`` legs down). The force of a step depends on nothing else, so the best total
force a side can produce in ``steps`` steps is a backward recursion over counts. Walking
straight, progress is ``c_u`` times the total force of both sides; the two sides are
independent, so the straight optimum is ``c_u (best_left + best_right)``.

When both sides have as many legs, running the same count sequence on both sides keeps the
moment at zero, so that optimum is reached by an actual posture sequence (the witness, checked
by integrating eqs. (14)-(16)). It is exact over every posture sequence when turning is off
(``c_theta = 0``) or the moment stays zero; exhaustive search on bodies of 1 and 2 legs a
side checks this (``tests/msm/test_msm_optimum.py``). With turning, that search also shows the
one way to beat it: a stroke at one heading and a back-stroke at another gain
``c_u (1 - cos dtheta)``, 0.025 mm a wiggle with the default constants (0.003 % of legged12's
optimum); this second-order gain is not counted.
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass
from functools import cache

import numpy as np

from qdsega.msm.model import MinimalSimulationModel, side_force
from qdsega.task import move_pose

Counts = tuple[int, int, int, int]


@dataclass(frozen=True)
class Optimum:
    """The straight-walk optimum and a posture sequence that reaches it.

    Attributes:
        distance_m: the largest distance toward the light one trial can cover (m).
        proven: True when the witness reaches the count-DP bound, walking straight at a light
            straight ahead (the optimum up to the turning wiggle of the module docstring); otherwise
            ``distance_m`` is what the witness covers, and ``bound_m`` only a reference.
        bound_m: ``c_u`` times the best total force of both sides (m).
        postures: the witness, start posture first, shape (steps + 1, J).
    """

    distance_m: float
    proven: bool
    bound_m: float
    postures: np.ndarray


@cache
def _compositions(total: int) -> tuple[tuple[int, int, int, int], ...]:
    """Every way to split ``total`` legs over the 4 target states."""
    return tuple(
        (a, b, c, d)
        for a, b, c, d in itertools.product(range(total + 1), repeat=4)
        if a + b + c + d == total
    )


def _side_moves(
    counts: Counts, u: float, v: float, min_down: int
) -> dict[Counts, tuple[float, np.ndarray]]:
    """Best step to each next-counts from ``counts``: next -> (force, 4x4 transition counts)."""
    every = np.array(list(itertools.product(*(_compositions(c) for c in counts))))  # (k, 4, 4)
    targets = every.sum(axis=1)  # next counts of each, (k, 4)
    forces = side_force(
        u * (every[:, 0, 1] - every[:, 1, 0]), v * (every[:, 0, 0] + every[:, 1, 1])
    )
    best: dict[Counts, tuple[float, np.ndarray]] = {}
    for k in np.flatnonzero(targets[:, 0] + targets[:, 1] >= min_down):
        nxt: Counts = tuple(targets[k].tolist())
        force = float(forces[k])
        if nxt not in best or force > best[nxt][0]:  # the first of equal forces stays
            best[nxt] = (force, every[k])
    return best


def _side_optimum(
    start: Counts, steps: int, u: float, v: float, min_down: int
) -> tuple[float, list[np.ndarray]]:
    """Best total force of one side over ``steps`` steps, and the transition matrices."""
    n = sum(start)
    all_counts: list[Counts] = list(_compositions(n))
    moves = {c: _side_moves(c, u, v, min_down) for c in all_counts}
    value = {c: 0.0 for c in all_counts}
    policy: list[dict[Counts, Counts]] = []
    for _ in range(steps):
        new_value, choice = {}, {}
        for c in all_counts:
            nxt, (force, _) = max(
                moves[c].items(), key=lambda item: (item[1][0] + value[item[0]], item[0])
            )
            new_value[c] = force + value[nxt]
            choice[c] = nxt
        value = new_value
        policy.insert(0, choice)
    matrices, c = [], start
    for choice in policy:
        nxt = choice[c]
        matrices.append(moves[c][nxt][1])
        c = nxt
    return value[start], matrices


def _apply(states: np.ndarray, matrix: np.ndarray) -> np.ndarray:
    """Move individual legs (states 1..4, shape (k,)) as a 4x4 count matrix says."""
    nxt = states.copy()
    for i in range(4):
        legs = np.flatnonzero(states == i + 1)
        targets = np.repeat(np.arange(1, 5), matrix[i])
        nxt[legs] = targets
    return nxt


def msm_optimum(
    model: MinimalSimulationModel, *, steps: int, light_xy: tuple[float, float]
) -> Optimum:
    """The exact straight-walk optimum of one trial of ``steps`` commanded postures.

    Args:
        model: the body and its MSM constants.
        steps: postures commanded per trial.
        light_xy: light position (m); the robot starts at the origin heading +x.
    """
    if steps < 1:
        raise ValueError(f"steps must be at least 1, got {steps}")
    p = model.params
    right = np.asarray(model.legs.right)
    start_states = model.legs.states(model.start_posture())
    sides = []
    for mask in (~right, right):
        one, two, three, four = (int(np.sum(start_states[mask] == s)) for s in (1, 2, 3, 4))
        counts = (one, two, three, four)
        sides.append(_side_optimum(counts, steps, p.u, p.v, p.min_down_per_side))
    bound = p.c_u * (sides[0][0] + sides[1][0])

    # The witness: the left side's count sequence on both sides when they match, else each
    # side its own (then the moment may turn the robot and the bound is not reached).
    symmetric = int(right.sum()) * 2 == len(right)
    plans = [sides[0][1], sides[0][1]] if symmetric else [sides[0][1], sides[1][1]]
    states = start_states.copy()
    postures = [model.start_posture()]
    for step in range(steps):
        for mask, plan in zip((~right, right), plans, strict=True):
            states[mask] = _apply(states[mask], plan[step])
        postures.append(model.legs.posture(states, base=postures[0]))
    sequence = np.array(postures)
    moves = model.transitions(sequence[:-1], sequence[1:])
    pose = (0.0, 0.0, 0.0)
    for t in range(steps):
        pose = move_pose(*pose, moves.dx[t, t], moves.dy[t, t], moves.dtheta[t, t])
    lx, ly = light_xy
    distance = math.hypot(lx, ly) - math.hypot(lx - pose[0], ly - pose[1])
    ahead = abs(ly) < 1e-12 and lx > 0
    proven = bool(ahead and abs(distance - bound) <= 1e-9 * max(1.0, bound))  # JSON-safe
    return Optimum(distance_m=distance, proven=proven, bound_m=bound, postures=sequence)
