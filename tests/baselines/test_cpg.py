import math

import numpy as np
import pytest

from qdsega.baselines.cpg import CPGGait
from qdsega.description import load_formation


@pytest.fixture(scope="module", params=["snake5", "quadruped"])
def formation(request):
    return load_formation(f"assemblies/{request.param}.yaml")


def _random_gait(formation, rng, period):
    return CPGGait.from_unit(
        formation, rng.uniform(size=3 * len(formation.joints)), period_steps=period
    )


def test_every_posture_is_the_nearest_level_of_the_sine(formation):
    rng = np.random.default_rng(0)
    for period in (3, 4, 7):
        gait = _random_gait(formation, rng, period)
        postures = gait.postures(formation, steps=12)
        assert postures.shape == (12, len(formation.joints))
        assert postures.dtype == np.int64
        k = np.arange(1, 13)[:, None]
        angles = np.array(gait.offset_rad) + np.array(gait.amplitude_rad) * np.sin(
            2 * math.pi * k / period + np.array(gait.phase_rad)
        )
        for j, joint in enumerate(formation.joints):
            levels = np.array(joint.levels_rad)
            chosen = levels[postures[:, j]]
            distance_to_nearest = np.abs(levels[None, :] - angles[:, [j]]).min(axis=1)
            assert np.allclose(np.abs(chosen - angles[:, j]), distance_to_nearest)


def test_postures_repeat_with_the_period(formation):
    rng = np.random.default_rng(1)
    for period in range(2, 9):
        postures = _random_gait(formation, rng, period).postures(formation, steps=30)
        assert np.array_equal(postures[period:], postures[:-period])


def test_unit_box_spans_each_joints_level_range(formation):
    n = len(formation.joints)
    lo = np.array([min(j.levels_rad) for j in formation.joints])
    hi = np.array([max(j.levels_rad) for j in formation.joints])
    low = CPGGait.from_unit(formation, np.zeros(3 * n), period_steps=4)
    high = CPGGait.from_unit(formation, np.ones(3 * n), period_steps=4)
    assert np.allclose(low.offset_rad, lo) and np.allclose(high.offset_rad, hi)
    assert np.allclose(low.amplitude_rad, 0) and np.allclose(high.amplitude_rad, hi - lo)
    # Zero amplitude: a constant posture; offsets at the bottom: every joint's lowest level.
    lowest = [int(np.argmin(j.levels_rad)) for j in formation.joints]
    assert (low.postures(formation, steps=5) == lowest).all()


def test_a_two_level_joint_becomes_a_square_wave():
    quadruped = load_formation("assemblies/quadruped.yaml")
    n = len(quadruped.joints)
    unit = np.concatenate([np.full(n, 0.5), np.full(n, 0.25), np.zeros(n)])
    postures = CPGGait.from_unit(quadruped, unit, period_steps=6).postures(quadruped, steps=6)
    # sin(2 pi k / 6) for k = 1..6: above the centre at k = 1, 2, on it at k = 3, below it at
    # k = 4, 5: the joint's upper level, then its lower one, whatever the amplitude.
    high = [int(np.argmax(j.levels_rad)) for j in quadruped.joints]
    low = [int(np.argmin(j.levels_rad)) for j in quadruped.joints]
    assert (postures[:2] == high).all()
    assert (postures[3:5] == low).all()


def test_round_trip_through_a_dict(formation):
    gait = _random_gait(formation, np.random.default_rng(2), 5)
    again = CPGGait.from_dict(gait.to_dict())
    assert again == gait
    assert np.array_equal(again.postures(formation, steps=9), gait.postures(formation, steps=9))


@pytest.mark.parametrize(
    "change, message",
    [
        ({"offset_rad": (0.0,)}, "one value per joint"),
        ({"amplitude_rad": (-0.1, 0.1)}, "non-negative"),
        ({"phase_rad": (math.nan, 0.0)}, "finite"),
        ({"period_steps": 1}, "at least 2"),
        ({"period_steps": 4.0}, "integer"),
    ],
)
def test_bad_parameters_are_refused(change, message):
    params = {
        "amplitude_rad": (0.1, 0.1),
        "offset_rad": (0.0, 0.0),
        "phase_rad": (0.0, 1.0),
        "period_steps": 4,
    } | change
    with pytest.raises(ValueError, match=message):
        CPGGait(**params)


def test_bad_unit_points_and_formations_are_refused(formation):
    n = len(formation.joints)
    with pytest.raises(ValueError, match="unit coordinates"):
        CPGGait.from_unit(formation, np.zeros(3 * n - 1), period_steps=4)
    with pytest.raises(ValueError, match=r"\[0, 1\]"):
        CPGGait.from_unit(formation, np.full(3 * n, 1.5), period_steps=4)
    other = CPGGait(amplitude_rad=(0.1,), offset_rad=(0.0,), phase_rad=(0.0,), period_steps=4)
    with pytest.raises(ValueError, match="joints"):
        other.postures(formation, steps=4)
    with pytest.raises(ValueError, match="keys"):
        CPGGait.from_dict({"period_steps": 4})
