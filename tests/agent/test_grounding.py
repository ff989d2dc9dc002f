"""A grounded table answers with observed moves: in context first, then in any context, then the
base table; it fails what failed more often than not; its state round-trips."""

from __future__ import annotations

import numpy as np
import pytest

from qdsega.agent.grounding import GroundedTransitions
from qdsega.agent.model import Transitions
from qdsega.agent.policy import Rollout
from qdsega.agent.space import ExplorationSpace
from qdsega.agent.table_model import TableModel
from qdsega.task import Task, TaskConfig

P = np.array([[0], [1], [2]])  # three postures of a one-joint body
_TASK = Task(config=TaskConfig(), light_xy=(50.0, 0.0))


class _Base:
    """Every move 1 cm forward."""

    n_joints = 1

    def start_posture(self) -> np.ndarray:
        return P[0]

    def transitions(self, from_postures, to_postures) -> Transitions:
        shape = (len(from_postures), len(to_postures))
        zeros = np.zeros(shape)
        return Transitions(dx=np.full(shape, 0.01), dy=zeros, dtheta=zeros, failed=zeros > 0)


def _trial(postures: list[int], xs: list[float], failed: bool = False) -> Rollout:
    poses = np.zeros((len(xs), 3))
    poses[:, 0] = xs
    return Rollout(
        actions=np.arange(len(postures)),
        postures=np.array(postures)[:, None],
        poses=poses,
        failed=failed,
        distance_m=xs[-1],
    )


def test_observed_moves_override_the_base_most_specific_first():
    table = GroundedTransitions(base=_Base())
    # 0 -> 1 (+0.10), 1 -> 2 (+0.20, entered from 0), 2 -> 1 (+0.30), 1 -> 2 (+0.40, from 2)
    assert table.observe(_trial([1, 2, 1, 2], [0.0, 0.1, 0.3, 0.6, 1.0]), P[0]) == 4
    t = table.transitions(P, P)
    assert t.dx[0, 1] == pytest.approx(0.1)
    assert t.dx[1, 2] == pytest.approx(0.3)  # mean over both contexts
    # Never observed: the base, less the RMS gap between observed and base forward moves.
    gap = np.sqrt(np.mean(np.square([0.1 - 0.01, 0.3 - 0.01, 0.3 - 0.01])))
    assert table.base_gap_m() == pytest.approx(gap)
    assert t.dx[0, 2] == pytest.approx(0.01 - gap)
    in_context, row = t.row(0, 1)  # 1 entered from 0
    assert in_context is t.in_context and in_context.dx[row, 2] == pytest.approx(0.2)
    in_context, row = t.row(2, 1)
    assert in_context.dx[row, 2] == pytest.approx(0.4)
    in_context, row = t.row(0, 1)
    assert in_context.dx[row, 0] == pytest.approx(0.01 - gap)  # the plain row where unobserved
    plain, row = t.row(1, 0)  # no observation after 1 -> 0
    assert plain is t and row == 0


def test_a_move_fails_where_it_failed_in_context_and_by_majority_elsewhere():
    table = GroundedTransitions(base=_Base())
    table.observe(_trial([1, 2], [0.0, 0.1, 0.1], failed=True), P[0])
    assert table.transitions(P, P).failed[1, 2]
    table.observe(_trial([1, 2], [0.0, 0.1, 0.2]), P[0])
    table.observe(_trial([1, 2], [0.0, 0.1, 0.2]), P[0])
    t = table.transitions(P, P)
    assert not t.failed[1, 2] and t.dx[1, 2] == pytest.approx(0.1)  # 2 moves, 1 failure
    in_context, row = t.row(0, 1)
    assert in_context.failed[row, 2]  # it failed once after 0 -> 1


def test_state_round_trips_and_refuses_another_body():
    table = GroundedTransitions(base=_Base())
    table.observe(_trial([1, 2, 1], [0.0, 0.1, 0.3, 0.2]), P[0])
    copy = GroundedTransitions(base=_Base())
    copy.restore(table.state())
    for a, b in zip(
        copy.transitions(P, P).compiled(), table.transitions(P, P).compiled(), strict=True
    ):
        assert np.array_equal(a, b)
    state = table.state()
    state["plain_keys"] = np.zeros((1, 4), dtype=np.int64)
    with pytest.raises(ValueError, match="do not fit"):
        copy.restore(state)


def test_a_restored_table_has_the_same_base_gap_bit_for_bit():
    """Observations come back sorted; the gap must not depend on the order they were seen."""
    rng = np.random.default_rng(2)  # one of many seeds whose gap differs in insertion order
    table = GroundedTransitions(base=_Base())
    for _ in range(30):
        postures = [int(p) for p in rng.permutation(20)[:8]]
        moves = 10.0 ** rng.uniform(-4, 0, 8)  # many magnitudes: the sum's order shows
        table.observe(_trial(postures, [0.0, *np.cumsum(moves)]), P[0])
    copy = GroundedTransitions(base=_Base())
    copy.restore(table.state())
    assert copy.base_gap_m() == table.base_gap_m()


def test_in_context_the_latest_move_holds_and_a_trial_start_is_a_context():
    table = GroundedTransitions(base=_Base())
    table.observe(_trial([1, 2], [0.0, 0.1, 0.3]), P[0])
    table.observe(_trial([1, 2], [0.0, 0.2, 0.3]), P[0])
    t = table.transitions(P, P)
    assert t.dx[0, 1] == pytest.approx(0.15)  # any context: the mean
    start, row = t.row(-1, 0)  # the trial's first move: the latest
    assert start is t.in_context and start.dx[row, 1] == pytest.approx(0.2)
    after, row = t.row(0, 1)
    assert after.dx[row, 2] == pytest.approx(0.1)


def test_a_remembered_trial_is_walked_exactly_whatever_later_trials_saw():
    """The same commands from a trial's start move as they did, even after another trial
    entered the same postures in the same context with other moves; a walk that leaves the
    remembered commands falls back to the context and plain rows."""
    table = GroundedTransitions(base=_Base())
    table.observe(_trial([1, 2, 1, 2], [0.0, 0.1, 0.3, 0.6, 1.0]), P[0])
    table.observe(_trial([2, 1, 2], [0.0, 0.05, 0.1, 0.12]), P[0])  # 1 -> 2 after 2 -> 1 again
    space = ExplorationSpace.from_population(P[1:], P[0])
    world = TableModel(
        space=space, table=table.transitions(space.postures, space.actions), task=_TASK
    )
    world.start_trial()
    for posture in ([1], [2], [1], [2]):
        world.command(np.array(posture))
    assert world.pose()[0] == pytest.approx(1.0)  # the first trial, move for move
    world.start_trial()
    for posture in ([1], [2], [2]):  # leaves the first trial at its third command
        world.command(np.array(posture))
    t = table.transitions(space.postures, space.actions)
    assert world.pose()[0] == pytest.approx(0.1 + 0.2 + t.dx[2, 1])


def test_paths_round_trip_and_refuse_a_malformed_tree():
    table = GroundedTransitions(base=_Base())
    table.observe(_trial([1, 2], [0.0, 0.1, 0.3]), P[0])
    table.observe(_trial([1, 1], [0.0, 0.1, 0.1], failed=True), P[0])
    state = table.state()
    assert state["path_parents"].tolist() == [0, 1, 1]  # 1, then 2 or (failed) 1 after it
    copy = GroundedTransitions(base=_Base())
    copy.restore(state)
    assert np.array_equal(copy.transitions(P, P).paths.child, table.transitions(P, P).paths.child)
    state["path_parents"] = np.array([0, 5, 1])
    with pytest.raises(ValueError, match="do not fit"):
        copy.restore(state)
