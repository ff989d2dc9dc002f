"""Learning dynamics on a posture-transition table, compiled: eqs. (1), (17), (18).

The Q-table has one row per state ``s = interior * n_exterior + exterior`` and one column per
action. A trial starts at the origin, heading +x, in interior state 0 (the initial posture),
and runs ``trial_steps`` commands or until the lower agent fails. Each step:

1. choose ``a`` by Boltzmann roulette at the trial's temperature, eq. (18), the trial counter
   restarting at 0 each generation (the schedule then explores afresh over a new table);
2. if the move fails: ``Q(s, a) <- (1 - alpha) Q(s, a) + alpha * penalty`` and the trial ends
   (a fall has no next state);
3. else move the robot by the table's body-frame displacement (the move of a remembered trial
   while the walk follows one since the trial's start, else the row for the posture the robot
   came from where the table has one), reward eq. (17), and update eq. (1) with
   ``max Q(s', .)``; the step that ends a trial by its length bootstraps like any
   other (a time limit is not a terminal state).

The rules (reward, exterior state, pose integration) are :mod:`qdsega.task`'s compiled kernels.
The helpers called at every step are compiled without reference counting
(:func:`qdsega.jit.njit_no_refcount`; 30 ns saved a call with three arrays, measured); such
helpers must not allocate arrays.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from qdsega.agent.boltzmann import (
    UNDERFLOW,
    boltzmann_select_fast,
    live_actions,
    temperature,
)
from qdsega.jit import njit_no_refcount
from qdsega.obstacle_map import SENSED_STATES
from qdsega.task import (
    edge_directions,
    exterior_state,
    exterior_state_ahead,
    move_position,
    sensed_exterior,
    step_reward,
    stopped,
)


@njit(cache=True)
def q_update(q: float, reward: float, best_next: float, alpha: float, gamma: float) -> float:
    """Eq. (1): ``(1 - alpha) Q + alpha (r + gamma max_a' Q(s', a'))``."""
    return (1.0 - alpha) * q + alpha * (reward + gamma * best_next)


@njit_no_refcount()
def _scan_row(row: np.ndarray, s: int, stats: np.ndarray, arg: np.ndarray) -> None:
    """Row ``s``'s statistics from scratch: ``stats[s] = (max, max over the other actions,
    1.0 = valid)`` and ``arg[s]`` the first action with the max (ties: the second max is the
    max)."""
    best = 0
    for a in range(1, row.shape[0]):
        if row[a] > row[best]:
            best = a
    second = -math.inf
    for a in range(row.shape[0]):
        if a != best and row[a] > second:
            second = row[a]
    stats[s, 0], stats[s, 1], stats[s, 2] = row[best], second, 1.0
    arg[s] = best


@njit_no_refcount()
def _row_top(q: np.ndarray, s: int, stats: np.ndarray, arg: np.ndarray) -> float:
    """max Q(s, .), rescanning row ``s`` where an update left its statistics stale."""
    if stats[s, 2] == 0.0:
        _scan_row(q[s], s, stats, arg)
    return stats[s, 0]


_FEW = 16
"""At most this many live actions in a row: the roulette walks only them."""
_SLACK = 50.0
"""Live actions are counted with this much room below the underflow (in ``Q / T``), so that
they stay a superset of those with weight while the row's max falls less than it times T."""


@njit_no_refcount()
def _choose(
    q: np.ndarray,
    s: int,
    stats: np.ndarray,
    arg: np.ndarray,
    members: np.ndarray,
    temp: float,
    u: float,
    scratch: np.ndarray,
    weights: np.ndarray,
    bits: np.ndarray,
) -> int:
    """Eq. (18)'s roulette over row ``s`` with pointer ``u``, from the row's statistics: the
    best action where no other has weight; the roulette over the row's live actions
    (``members[s]``, kept while the row's max does not fall) where at most :data:`_FEW`
    have; else over the whole row."""
    top = _row_top(q, s, stats, arg)
    if (stats[s, 1] - top) * (1.0 / temp) <= UNDERFLOW:
        return arg[s]
    live, since = stats[s, 3], stats[s, 4]
    if (
        live == -2.0
        or (live == -1.0 and temp <= 0.5 * since)
        or (live >= 0.0 and (temp > since or (stats[s, 5] - top) / temp > 0.5 * _SLACK))
    ):
        live = float(live_actions(q[s], top, temp, _SLACK, _FEW, members[s]))
        stats[s, 3], stats[s, 4], stats[s, 5] = live, temp, top
    if live >= 0.0:
        # The roulette over the live actions' values alone draws the same action.
        m = int(live)
        for j in range(m):
            scratch[j] = q[s, members[s, j]]
        j = boltzmann_select_fast(scratch[:m], top, top, 0, temp, u, weights, bits)
        return members[s, j]
    return boltzmann_select_fast(q[s], top, stats[s, 1], arg[s], temp, u, weights, bits)


@njit_no_refcount()
def _update_stats(s: int, a: int, new: float, stats: np.ndarray, arg: np.ndarray) -> None:
    """Keep row ``s``'s statistics (valid ones) after Q(s, a) became ``new``: the bound on
    the second max holds as the others fall, and the row is rescanned once its best falls
    below it."""
    top, second = stats[s, 0], stats[s, 1]
    if a == arg[s]:
        if new >= second:
            stats[s, 0] = new
        else:
            stats[s, 2] = 0.0
    elif new > top:
        stats[s, 0], stats[s, 1] = new, top
        arg[s] = a
    elif new >= second:
        stats[s, 1] = new


@njit(cache=True)
def learn_on_table(
    q: np.ndarray,
    dx: np.ndarray,
    dy: np.ndarray,
    dtheta: np.ndarray,
    failed: np.ndarray,
    context: np.ndarray,
    context_dx: np.ndarray,
    context_dy: np.ndarray,
    context_dtheta: np.ndarray,
    context_failed: np.ndarray,
    path_child: np.ndarray,
    path_dx: np.ndarray,
    path_dy: np.ndarray,
    path_dtheta: np.ndarray,
    path_failed: np.ndarray,
    next_interior: np.ndarray,
    light: np.ndarray,
    edges: np.ndarray,
    near: np.ndarray,
    ahead: np.ndarray,
    geometry: np.ndarray,
    fan: np.ndarray,
    outline: np.ndarray,
    trials: int,
    trial_steps: int,
    alpha: float,
    gamma: float,
    temperature_params: np.ndarray,
    reward_per_m: float,
    penalty: float,
    rng: np.random.Generator,
    uses: np.ndarray,
    distances: np.ndarray,
    fell: np.ndarray,
) -> int:
    """One generation of Q-learning (module docstring). Updates ``q`` in place.

    Args:
        q: Q-table, shape (n_interior * n_exterior, A), updated in place.
        dx, dy, dtheta, failed: the transition table, shape (n_interior, A) (m, m, rad, bool).
        context: ``context[h, i]``: the row of the ``context_*`` arrays for moves from interior
            state ``i`` entered from ``h`` (``h = n_interior``: the trial's start), or -1 for
            row ``i`` of the plain table, shape (n_interior + 1, n_interior)
            (:class:`qdsega.agent.model.Transitions`).
        context_dx, context_dy, context_dtheta, context_failed: those rows, shape (R, A).
        path_child, path_dx, path_dy, path_dtheta, path_failed: remembered trials
            (:class:`qdsega.agent.model.Paths`): node reached by each action from each node,
            shape (N, A), node 0 a trial's start; the move into each node, shape (N,).
        next_interior: interior state each action leads to, shape (A,).
        light: light position (x, y) (m).
        edges: the light's bin edges (rad), shape (n_light,).
        near, ahead, geometry, fan, outline: the obstacles
            (:meth:`qdsega.task.Task.map_arrays`): empty grids where nothing stands; else the
            exterior states are the light's bins times the sensed states.
        trials, trial_steps: trials of this generation and commands per trial.
        alpha, gamma: eq. (1).
        temperature_params: (scale, rate, offset) of eq. (18).
        reward_per_m, penalty: eq. (17)'s reward per metre gained and the failure reward.
        rng: the only source of randomness (one uniform per step).
        uses: per-action use counts, shape (A,), incremented (eq. 5's N_u).
        distances: per-trial distance covered toward the light (m), shape (trials,), written.
        fell: per-trial failure flag, shape (trials,), written.

    Returns:
        The number of steps (commands) taken.
    """
    n_light = edges.shape[0]
    n_exterior = n_light * (1 if ahead.shape[0] == 0 else SENSED_STATES)
    n_interior = dx.shape[0]
    scratch, weights = np.empty(q.shape[1]), np.empty(q.shape[1])
    bits = np.empty(q.shape[1], dtype=np.int64)
    # Per row: max Q, a bound on the max over the other actions (exact after a scan), valid
    # flag, and the best action (eq. 1's max, the roulette's shift and its greedy shortcut),
    # rescanned only when an update may have lowered the max; then how many live actions
    # ``members`` holds (-1: more than _FEW, -2: not known), and the temperature and max Q
    # they were counted at.
    stats = np.zeros((q.shape[0], 6))
    stats[:, 3] = -2.0
    arg = np.zeros(q.shape[0], dtype=np.int64)
    members = np.empty(q.shape, dtype=np.int64)
    directions = edge_directions(edges)
    light_x, light_y = light[0], light[1]
    d_start = math.hypot(light_x, light_y)
    steps = 0
    for trial in range(trials):
        temp = temperature(
            trial, temperature_params[0], temperature_params[1], temperature_params[2]
        )
        x, y, theta, cos_theta, sin_theta = 0.0, 0.0, 0.0, 1.0, 0.0
        d = d_start
        previous, interior, node = -1, 0, 0
        exterior = sensed_exterior(
            exterior_state(x, y, theta, light_x, light_y, edges),
            n_light, ahead, geometry, fan, x, y, theta,
        )  # fmt: skip
        fell[trial] = False
        for _ in range(trial_steps):
            s = interior * n_exterior + exterior
            a = _choose(q, s, stats, arg, members, temp, rng.random(), scratch, weights, bits)
            uses[a] += 1
            steps += 1
            old = q[s, a]
            node = path_child[node, a] if node >= 0 else -1
            if node >= 0:
                fails = path_failed[node]
                mx, my, mt = path_dx[node], path_dy[node], path_dtheta[node]
            else:
                r = context[previous if previous >= 0 else n_interior, interior]
                if r < 0:
                    fails = failed[interior, a]
                    mx, my, mt = dx[interior, a], dy[interior, a], dtheta[interior, a]
                else:
                    fails = context_failed[r, a]
                    mx, my, mt = context_dx[r, a], context_dy[r, a], context_dtheta[r, a]
            if fails:
                q[s, a] = (1.0 - alpha) * old + alpha * penalty
                _update_stats(s, a, q[s, a], stats, arg)
                fell[trial] = True
                break
            x_new, y_new = move_position(x, y, cos_theta, sin_theta, mx, my)
            if stopped(near, geometry, outline, x_new, y_new, theta + mt):
                mt = 0.0  # run into an obstacle: the move is lost
            else:
                x, y = x_new, y_new
            theta += mt
            cos_theta, sin_theta = math.cos(theta), math.sin(theta)
            d_new = math.hypot(light_x - x, light_y - y)
            previous, interior = interior, next_interior[a]
            exterior = sensed_exterior(
                exterior_state_ahead(
                    x, y, theta, cos_theta, sin_theta, light_x, light_y, edges, directions
                ),
                n_light, ahead, geometry, fan, x, y, theta,
            )  # fmt: skip
            best_next = _row_top(q, interior * n_exterior + exterior, stats, arg)
            q[s, a] = q_update(old, step_reward(d, d_new, reward_per_m), best_next, alpha, gamma)
            _update_stats(s, a, q[s, a], stats, arg)
            d = d_new
        distances[trial] = d_start - d
    return steps
