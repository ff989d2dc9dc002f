"""Learning curves: a step function of the budget, kept as JSON."""

from __future__ import annotations

import numpy as np
import pytest

from qdsega.bench.curve import Curve

CURVE = Curve.of([(10, 0.1, 1.0), (30, 0.5, 2.0), (100, 0.4, 3.0)])


def test_a_curve_holds_its_last_value_and_scores_zero_before_its_first_point():
    assert CURVE.at(np.array([5, 10, 29, 30, 99, 1000])).tolist() == [0, 0.1, 0.1, 0.5, 0.5, 0.4]


def test_the_first_point_reaching_a_distance_gives_its_steps_and_wall_time():
    assert CURVE.first_reaching(0.3) == (30, 2.0)
    assert CURVE.first_reaching(0.6) is None


def test_until_keeps_the_points_within_the_budget():
    assert CURVE.until(30).steps.tolist() == [10, 30]


def test_a_curve_survives_a_round_trip_through_json(tmp_path):
    CURVE.save(tmp_path / "c.json", key="k")
    again = Curve.load(tmp_path / "c.json")
    for name in ("steps", "distance_m", "wall_s"):
        assert np.array_equal(getattr(again, name), getattr(CURVE, name))


def test_bad_curves_are_refused():
    with pytest.raises(ValueError, match="decrease"):
        Curve.of([(10, 0.1, 1.0), (5, 0.2, 2.0)])
    with pytest.raises(ValueError, match="one value per point"):
        Curve(np.array([1, 2]), np.array([0.1]), np.array([0.0, 1.0]))
