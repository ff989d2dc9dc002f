import numpy as np
import pytest

from qdsega.description import load_formation
from qdsega.locomotion.lower_agent import LowerAgentConfig
from qdsega.locomotion.memo import MeasuredTransitions


@pytest.fixture(scope="module")
def snake5():
    return load_formation("assemblies/snake5.yaml")


def _postures(count: int) -> np.ndarray:
    return np.random.default_rng(0).integers(0, 9, size=(count, 4))


def test_measurements_do_not_depend_on_order_or_workers(snake5):
    postures = _postures(3)
    serial = MeasuredTransitions(formation=snake5, lower_agent=LowerAgentConfig(), workers=1)
    forward = serial.transitions(postures, postures[::-1])
    reverse = MeasuredTransitions(formation=snake5, lower_agent=LowerAgentConfig(), workers=1)
    backward = reverse.transitions(postures[::-1], postures)
    assert np.array_equal(forward.dx, backward.dx[::-1, ::-1])
    assert np.array_equal(forward.dtheta, backward.dtheta[::-1, ::-1])
    parallel = MeasuredTransitions(formation=snake5, lower_agent=LowerAgentConfig(), workers=2)
    try:
        assert np.array_equal(parallel.transitions(postures, postures[::-1]).dx, forward.dx)
    finally:
        parallel.close()


def test_each_transition_is_measured_once_and_survives_a_save(snake5, tmp_path):
    postures = _postures(3)
    memo = MeasuredTransitions(formation=snake5, lower_agent=LowerAgentConfig(), workers=1)
    first = memo.transitions(postures, postures)
    assert memo.measured == 9
    memo.transitions(postures[:2], postures)
    assert memo.measured == 9
    memo.save(tmp_path / "memo.npz")
    again = MeasuredTransitions(formation=snake5, lower_agent=LowerAgentConfig(), workers=1)
    again.load(tmp_path / "memo.npz")
    assert len(again) == 9
    second = again.transitions(postures, postures)
    assert again.measured == 0
    for field in ("dx", "dy", "dtheta", "failed"):
        assert np.array_equal(getattr(first, field), getattr(second, field))


def test_staying_put_goes_nowhere_and_a_wave_step_moves(snake5):
    memo = MeasuredTransitions(formation=snake5, lower_agent=LowerAgentConfig(), workers=1)
    still = np.array([[4, 4, 4, 4]])
    assert abs(memo.transitions(still, still).dx[0, 0]) < 1e-3
    bent = memo.transitions(np.array([[0, 4, 8, 4]]), np.array([[4, 8, 4, 0]]))
    assert not bent.failed[0, 0]
    assert np.hypot(bent.dx[0, 0], bent.dy[0, 0]) > 1e-3


def test_failures_are_recorded_for_a_legged_body():
    quadruped = load_formation("assemblies/quadruped.yaml")
    memo = MeasuredTransitions(formation=quadruped, lower_agent=LowerAgentConfig(), workers=1)
    start = np.array([quadruped.rest_levels()])
    all_up = start.copy()
    for leg in quadruped.legs:
        all_up[0, quadruped.joint_index(leg.lift_joint)] = 1
    table = memo.transitions(start, np.vstack([start, all_up]))
    assert list(table.failed[0]) == [False, True]


def test_a_mirrored_table_measures_one_of_each_mirror_pair():
    quadruped = load_formation("assemblies/quadruped.yaml")
    image = np.array(quadruped.mirror)
    rng = np.random.default_rng(3)
    sources, targets = rng.integers(0, 2, size=(2, 3, 8))
    both_sources = np.concatenate([sources, sources[:, image]])
    both_targets = np.concatenate([targets, targets[:, image]])
    plain = MeasuredTransitions(formation=quadruped, lower_agent=LowerAgentConfig(), workers=1)
    mirrored = MeasuredTransitions(
        formation=quadruped, lower_agent=LowerAgentConfig(), workers=1, mirror=True
    )
    full = plain.transitions(both_sources, both_targets)
    half = mirrored.transitions(both_sources, both_targets)
    assert plain.measured == 36 and mirrored.measured == 18
    # every entry is measured exactly where the mirrored table measured it, its mirror image
    # elsewhere: the same forward move and failure, the side move and turn negated
    back = np.concatenate([np.arange(3, 6), np.arange(3)])  # row/column of each mirror
    for name, sign in (("dx", 1), ("dy", -1), ("dtheta", -1), ("failed", 1)):
        got = getattr(half, name)
        assert np.array_equal(got, sign * getattr(half, name)[np.ix_(back, back)]), name
        measured = getattr(full, name)
        assert np.sum(got == measured) >= 18, name
    # the mirrored table's entries are within PyBullet's asymmetry of the full table's
    ok = ~(full.failed | half.failed)
    assert np.abs(full.dx[ok] - half.dx[ok]).max() < 0.02
    assert np.mean(full.failed == half.failed) > 0.9


def test_mirror_is_refused_for_a_body_without_one(snake5):
    assert snake5.mirror is None
    with pytest.raises(ValueError, match="snake5 has no left-right mirror"):
        MeasuredTransitions(formation=snake5, lower_agent=LowerAgentConfig(), mirror=True)
