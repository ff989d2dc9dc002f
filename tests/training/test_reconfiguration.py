"""Joints matched by name across two versions of a formation, by hand on tiny bodies: dropped,
added, locked and re-levelled joints; a policy replayed on the new body; a warm start."""

import math
import textwrap

import numpy as np
import pytest

from qdsega.agent.learner import LearnerState
from qdsega.agent.policy import GreedyPolicy
from qdsega.agent.space import ExplorationSpace
from qdsega.description import load_formation
from qdsega.description.shipped import UNITS_DIR
from qdsega.training.joint_mapping import JointMapping, describe
from qdsega.training.reconfiguration import warm_state

CHAIN = """\
name: {name}
light: {{distance_m: 5}}
units_dir: {units}
units:
  - {{name: a, unit: servo}}
{rest}
"""


def _chain(tmp_path, name: str, *units: str):
    rest = "\n".join(f"  - {{name: {u}}}" for u in units)
    file = tmp_path / f"{name}.yaml"
    file.write_text(textwrap.dedent(CHAIN).format(name=name, units=UNITS_DIR, rest=rest))
    return load_formation(file)


def _joint(name: str, parent: str, levels: str) -> str:
    return f"{name}, unit: servo, parent: {parent}, connector: back, axis: yaw, {levels}"


@pytest.fixture
def old(tmp_path):
    """Joints b, c, d of levels -20, 0, 20 deg."""
    levels = "levels_deg: [-20, 0, 20]"
    return _chain(
        tmp_path,
        "old",
        _joint("b", "a", levels),
        _joint("c", "b", levels),
        _joint("d", "c", levels),
    )


@pytest.fixture
def new(tmp_path):
    """c gone (its unit renamed x), d locked, b re-levelled, e added."""
    return _chain(
        tmp_path,
        "new",
        _joint("b", "a", "levels_deg: [-30, -10, 10, 30]"),
        _joint("x", "b", "levels_deg: [-20, 0, 20]"),
        _joint("d", "x", "locked_deg: 20"),
        _joint("e", "d", "levels_deg: [-5, 5]"),
    )


def test_joints_are_matched_by_name_and_levels_by_nearest_angle(old, new):
    mapping = JointMapping.between(old, new)
    assert mapping.report() == {
        "matched": ["b_joint"],
        "dropped": ["c_joint"],
        "locked": ["d_joint"],
        "added": ["x_joint", "e_joint"],
    }
    assert mapping.column.tolist() == [0, -1, -1]  # new b, x, e from old b, -, -
    # old b at -20, 0, 20 deg onto -30, -10, 10, 30: each as near to two; the first wins
    assert mapping.levels[0].tolist() == [0, 1, 2]
    fill = np.array([9, 8, 7])
    assert mapping.postures(np.array([[0, 1, 2], [2, 2, 2]]), fill).tolist() == [
        [0, 8, 7],
        [2, 8, 7],
    ]
    assert describe(mapping.report()) == (
        "1 joints matched, 1 dropped (c_joint), 1 locked (d_joint), 2 added (x_joint, e_joint)"
    )


def test_unrelated_bodies_share_nothing(old, tmp_path):
    other = _chain(tmp_path, "other", _joint("p", "a", "levels_deg: [0, 10]"))
    mapping = JointMapping.between(old, other)
    assert mapping.matched == () and mapping.added == ("p_joint",)
    assert mapping.dropped == ("b_joint", "c_joint", "d_joint")


def test_a_policy_on_the_new_body_keeps_its_table_and_holds_added_joints_at_rest(old, new):
    policy = GreedyPolicy(
        q=np.arange(12.0).reshape(4, 3),
        actions=np.array([[0, 0, 0], [2, 1, 0], [1, 2, 2]]),
        postures=np.array([[1, 1, 1], [0, 0, 0]]),
        next_interior=np.array([1, 0, 0]),
    )
    moved = JointMapping.between(old, new).policy(policy, new)
    rest = list(new.rest_levels())  # b: -10 deg (first of the nearest), x: 0 deg, e: -5 deg
    assert rest == [1, 1, 0]
    assert moved.actions.tolist() == [[0, 1, 0], [2, 1, 0], [1, 1, 0]]
    assert moved.postures.tolist() == [rest, [0, 1, 0]]  # a trial starts at the new rest
    assert np.array_equal(moved.q, policy.q)
    assert np.array_equal(moved.next_interior, policy.next_interior)


def test_a_warm_state_keeps_half_the_mapped_population_and_its_table(old, new):
    population = np.array([[0, 0, 0], [2, 1, 0], [0, 0, 0], [1, 1, 1]])
    space = ExplorationSpace.from_population(population, np.array([1, 1, 1]))
    q = np.arange(space.n_interior * 4 * space.n_actions, dtype=float).reshape(-1, space.n_actions)
    source = LearnerState(
        completed=5,
        population=population,
        rng_state={},
        previous=(space, q),
        elite=(population[:2], 1.5),
        elite_path=np.array([[2, 1, 0], [0, 0, 0], [2, 1, 0]]),
    )
    mapping = JointMapping.between(old, new)
    levels = np.array([len(j.levels_rad) for j in new.joints])
    start = np.array(new.rest_levels())
    state = warm_state(
        mapping, source, levels=levels, start=start, population=4, rng=np.random.default_rng(0)
    )
    # the old elite path, mapped with added joints at the start level, is the elite, untried
    assert state.completed == 0 and state.elite[1] is None
    assert state.elite_path.tolist() == [[2, 1, 0], [0, 1, 0], [2, 1, 0]]
    assert state.elite[0].tolist() == [[0, 1, 0], [2, 1, 0]]
    mapped, carried = state.previous
    kept = state.population[:2]  # KEPT_SHARE of 4: drawn from the mapped old population
    assert all(row.tolist() in mapped.actions.tolist() for row in kept)
    assert {row[0] for row in kept} <= {0, 2, 1}  # b at the nearest level of an old one
    assert all(0 <= row[1] < 3 and 0 <= row[2] < 2 for row in state.population)
    # every old action maps to one new posture: the two copies of [0 0 0] stay one action
    assert len(np.unique(mapped.actions, axis=0)) == len(space.actions) == 3
    assert carried is q and mapped.postures[0].tolist() == start.tolist()
    # interior k > 0 is the (mapped) posture of the action that leads there
    for a, k in enumerate(mapped.next_interior):
        if k > 0:
            assert mapped.postures[k].tolist() == mapped.actions[a].tolist()
    again = warm_state(
        mapping, source, levels=levels, start=start, population=4, rng=np.random.default_rng(0)
    )
    assert np.array_equal(again.population, state.population)  # the seed decides the draws
    bigger = warm_state(
        mapping, source, levels=levels, start=start, population=7, rng=np.random.default_rng(0)
    )
    assert len(bigger.population) == 7


def test_the_mapping_and_its_source_round_trip(old, new, tmp_path):
    population = np.array([[0, 0, 0], [2, 1, 0]])
    space = ExplorationSpace.from_population(population, np.array([1, 1, 1]))
    source = LearnerState(
        completed=3,
        population=population,
        rng_state={},
        previous=(space, np.ones((space.n_interior * 4, space.n_actions))),
        elite=(np.zeros((0, 3), dtype=np.int64), None),
        elite_path=np.array([[2, 1, 0]]),
    )
    mapping = JointMapping.between(old, new)
    mapping.save(tmp_path / "warm.npz", source)
    loaded, state = JointMapping.load(tmp_path / "warm.npz")
    assert state.elite_path.tolist() == [[2, 1, 0]]
    assert loaded.report() == mapping.report()
    assert np.array_equal(loaded.levels, mapping.levels)
    assert np.array_equal(state.population, population)
    assert np.array_equal(state.previous[0].actions, space.actions)
    assert math.isclose(state.previous[1].sum(), source.previous[1].sum())
