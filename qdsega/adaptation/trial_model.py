"""Which gait to try next on a changed body: a Gaussian process over the archive's behaviour
space whose prior mean is each elite's fitness on the intact body, corrected by every trial
on the changed one (Intelligent Trial and Error, Cully et al. 2015).

Our own few lines of numpy, not scikit-learn's ``GaussianProcessRegressor``: IT&E's model has a
fixed kernel (no hyperparameters to fit), a prior mean per point and at most a few dozen
observations, so the posterior is one small Cholesky solve, and the core dependencies stay as
they are.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

LENGTH_SCALE = 0.2
"""The Matérn kernel's length scale in the unit behaviour space (IT&E's is 0.4). At 0.4, a
trial that fails on the changed body lowers the prediction for most of a measured-contact
archive, and the search stops before it reaches the better gaits the archive holds."""
KAPPA = 0.05
"""The upper confidence bound's weight on the posterior's standard deviation (IT&E's 0.05)."""
STOP_OPTIMISM = 0.5
"""The search stops once the best trial reaches every untried cell's posterior mean plus this
many standard deviations: an untried gait the model is unsure of may still beat it."""
NOISE_SHARE = 0.03
"""The observation noise's standard deviation, as a share of the kernel's signal (-)."""


def matern52(a: np.ndarray, b: np.ndarray, length_scale: float) -> np.ndarray:
    """The Matérn 5/2 correlation between the rows of ``a`` (n, D) and ``b`` (m, D), (n, m)."""
    distance = np.sqrt(np.maximum(np.sum((a[:, None, :] - b[None, :, :]) ** 2, axis=2), 0.0))
    r = np.sqrt(5.0) * distance / length_scale
    return (1.0 + r + r**2 / 3.0) * np.exp(-r)


@dataclass
class TrialModel:
    """The posterior over every archive cell's fitness on the changed body.

    Attributes:
        descriptors: the elites' descriptors (C, D).
        prior: their fitness on the intact body, the prior mean (C,) (m).
        signal: the kernel's standard deviation (m): how far a trial may move the prior.
        length_scale: as :data:`LENGTH_SCALE`.
        kappa: as :data:`KAPPA`.
        tried: the cells tried so far, in order.
        observed: their fitness on the changed body (m).
    """

    descriptors: np.ndarray
    prior: np.ndarray
    signal: float
    length_scale: float = LENGTH_SCALE
    kappa: float = KAPPA
    tried: list[int] = field(default_factory=list)
    observed: list[float] = field(default_factory=list)

    def __post_init__(self) -> None:
        self.descriptors = np.asarray(self.descriptors, dtype=np.float64)
        self.prior = np.asarray(self.prior, dtype=np.float64)
        if self.descriptors.ndim != 2 or self.prior.shape != (len(self.descriptors),):
            raise ValueError(
                f"descriptors (C, D) and prior (C,) do not fit: {self.descriptors.shape}, "
                f"{self.prior.shape}"
            )
        if not len(self.prior) or not np.all(np.isfinite(self.prior)):
            raise ValueError("the prior needs at least one finite fitness, and only finite ones")
        if not (self.signal > 0 and self.length_scale > 0 and self.kappa >= 0):
            raise ValueError("signal and length_scale must be positive, kappa not negative")

    def posterior(self) -> tuple[np.ndarray, np.ndarray]:
        """The posterior mean (C,) (m) and standard deviation (C,) (m) of every cell."""
        if not self.tried:
            return self.prior.copy(), np.full(len(self.prior), self.signal)
        x = self.descriptors[self.tried]
        noise = (NOISE_SHARE * self.signal) ** 2
        gram = self.signal**2 * matern52(x, x, self.length_scale) + noise * np.eye(len(x))
        cross = self.signal**2 * matern52(self.descriptors, x, self.length_scale)  # (C, n)
        factor = np.linalg.cholesky(gram)
        residual = np.asarray(self.observed) - self.prior[self.tried]
        weights = np.linalg.solve(factor.T, np.linalg.solve(factor, residual))
        mean = self.prior + cross @ weights
        v = np.linalg.solve(factor, cross.T)  # (n, C)
        variance = np.maximum(self.signal**2 - np.sum(v**2, axis=0), 0.0)
        return mean, np.sqrt(variance)

    def next_cell(self) -> int:
        """The untried cell of the highest upper confidence bound (the first of equals)."""
        mean, std = self.posterior()
        bound = mean + self.kappa * std
        bound[self.tried] = -np.inf
        if np.all(np.isneginf(bound)):
            raise ValueError("every cell has been tried")
        return int(np.argmax(bound))

    def tell(self, cell: int, fitness: float) -> None:
        """What trying ``cell``'s gait on the changed body gave (m)."""
        if not 0 <= cell < len(self.prior) or cell in self.tried:
            raise ValueError(f"cell {cell} is not an untried cell of the archive")
        if not np.isfinite(fitness):
            raise ValueError(f"fitness must be finite, got {fitness}")
        self.tried.append(int(cell))
        self.observed.append(float(fitness))

    def done(self, max_trials: int) -> bool:
        """Whether to stop: ``max_trials`` tried, every cell tried, or no untried cell is
        predicted to beat the best trial (:meth:`settled`)."""
        if len(self.tried) >= min(max_trials, len(self.prior)):
            return True
        return self.settled()

    def settled(self) -> bool:
        """Whether the best trial is at least every untried cell's posterior mean plus
        :data:`STOP_OPTIMISM` standard deviations. IT&E stops at 0.9 of the best mean; that,
        and the plain mean, ended the search before it reached gaits the archive held."""
        if not self.tried:
            return False
        mean, std = self.posterior()
        bound = mean + STOP_OPTIMISM * std
        bound[self.tried] = -np.inf
        return max(self.observed) >= float(np.max(bound))
