import math

import numpy as np

from qdsega.analysis.evaluation import wave_of
from qdsega.baselines import classic_gaits
from qdsega.description import load_formation


def test_wave_of_a_serpenoid_finds_its_period_and_phase_lag():
    snake = load_formation("assemblies/snake10.yaml")
    postures = classic_gaits.serpenoid(
        snake,
        amplitude_rad=math.radians(20),
        phase_lag_rad=math.radians(60),
        steps_per_cycle=6,
        steps=24,
    )
    wave = wave_of(snake, postures)
    assert wave["period_steps"] == 6
    assert wave["phase_lag_deg"] == [60.0] * 8
    assert np.array(wave["joint_angles_deg"]).shape == (24, 9)


def test_wave_of_a_still_body_has_no_rhythm():
    snake = load_formation("assemblies/snake5.yaml")
    wave = wave_of(snake, np.tile([4, 4, 4, 4], (8, 1)))
    assert wave["period_steps"] == 2  # constant postures repeat at every shift; shortest wins
    assert wave["phase_lag_deg"] == [] and wave["mean_phase_lag_deg"] is None
