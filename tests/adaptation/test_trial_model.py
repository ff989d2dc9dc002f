"""The trial model: the prior where nothing was tried, the trials where they were, and the
stopping rule on a toy function with a known best."""

import numpy as np
import pytest

from qdsega.adaptation.trial_model import TrialModel

X = np.linspace(0.0, 1.0, 41)[:, None]


def test_without_trials_the_posterior_is_the_prior():
    model = TrialModel(descriptors=X, prior=np.sin(3 * X[:, 0]), signal=0.5)
    mean, std = model.posterior()
    assert np.array_equal(mean, np.sin(3 * X[:, 0])) and np.all(std == 0.5)
    assert model.next_cell() == int(np.argmax(np.sin(3 * X[:, 0])))


def test_a_trial_pulls_the_mean_to_what_it_found_and_its_neighbours_along():
    model = TrialModel(descriptors=X, prior=np.ones(41), signal=1.0)
    model.tell(20, 0.0)
    mean, std = model.posterior()
    assert mean[20] == pytest.approx(0.0, abs=0.01) and std[20] < 0.05
    assert mean[21] < 0.05 < 0.5 < mean[0] < 1.0  # near it pulled down most, far from it less


def test_the_search_stops_near_the_known_best_of_a_toy_function():
    """The intact body's map says the best gait is at 0.2; on the changed body gaits near 0.2
    fail and the true best is at 0.8 (0.9 of the prior's best there)."""
    prior = np.exp(-((X[:, 0] - 0.2) ** 2) / 0.02) + 0.9 * np.exp(-((X[:, 0] - 0.8) ** 2) / 0.02)
    truth = prior * (X[:, 0] > 0.5)
    model = TrialModel(descriptors=X, prior=prior, signal=float(prior.std()))
    while not model.done(max_trials=20):
        cell = model.next_cell()
        model.tell(cell, float(truth[cell]))
    assert len(model.tried) <= 20
    assert max(model.observed) == truth.max()  # it went on until it found the true best
    assert model.settled()  # and stopped there: nothing untried was predicted to beat it
    again = TrialModel(descriptors=X, prior=prior, signal=float(prior.std()))
    while not again.done(max_trials=20):
        cell = again.next_cell()
        again.tell(cell, float(truth[cell]))
    assert again.tried == model.tried  # no randomness: the same trials


def test_the_search_stops_after_its_trials_when_nothing_is_good_enough():
    model = TrialModel(descriptors=X, prior=np.ones(41), signal=0.1)
    for _ in range(3):
        model.tell(model.next_cell(), 0.0)
    assert model.done(max_trials=3) and not model.done(max_trials=4)


def test_bad_input_is_refused():
    with pytest.raises(ValueError, match="do not fit"):
        TrialModel(descriptors=X, prior=np.ones(3), signal=1.0)
    model = TrialModel(descriptors=X, prior=np.ones(41), signal=1.0)
    model.tell(0, 1.0)
    with pytest.raises(ValueError, match="untried"):
        model.tell(0, 1.0)
