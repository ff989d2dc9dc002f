"""Could a legged run measure fewer memo transitions? Two checks on a finished run's table.

Usage: .venv/bin/python experiments/memo_speed/memo_shortcuts.py RUN [--seed 0]

RUN is a memo-mode run folder of a legged body; its ``transitions.npz`` holds every transition
the run measured in PyBullet. Nothing is simulated.

1. Legs in the air. A leg that is up before and after a move touches nothing, so its swing
   level there should barely matter. The table's posture pairs are counted again with such a
   leg's "before" swing set to its "after" swing (up in both), then with every lifted leg's
   "before" swing so set: the fewer distinct pairs, the fewer measurements needed.
2. A model in place of measurements. Per leg, the (before, after) leg state (4 x 4 one-hot),
   summed linearly over the legs as the MSM's forces are (eqs. 7-13), fitted by least squares
   to 80 % of the moves that did not fail and scored on the other 20 % (R^2 of dx, dy,
   dtheta); failures predicted by the 5 nearest measured pairs (Hamming distance over both
   postures), against always guessing the commoner outcome.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

from qdsega.errors import QdsegaError
from qdsega.msm.legs import LegLayout
from qdsega.training.finished_run import FinishedRun
from qdsega.training.run_folder import RunFolder

_HOLDOUT = 0.2
_NEIGHBOURS = 5
_CHUNK = 256  # held-out rows per block of Hamming distances (bounds memory)


def distinct(before: np.ndarray, after: np.ndarray) -> int:
    """Distinct (before, after) rows of two (n, J) arrays."""
    return len(np.unique(np.hstack([before, after]), axis=0))


def r_squared(truth: np.ndarray, prediction: np.ndarray) -> float:
    """1 - residual variance / variance."""
    return float(1.0 - np.var(truth - prediction) / np.var(truth))


def nearest_rows(queries: np.ndarray, rows: np.ndarray, k: int) -> np.ndarray:
    """Indices of the k rows nearest each query in Hamming distance, ties by index: (n, k)."""
    blocks = []
    for start in range(0, len(queries), _CHUNK):
        distance = (queries[start : start + _CHUNK, None, :] != rows[None, :, :]).sum(axis=2)
        blocks.append(np.argsort(distance, axis=1, kind="stable")[:, :k])
    return np.concatenate(blocks)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("run", type=Path)
    parser.add_argument("--seed", type=int, default=0, help="draws the held-out 20 %%")
    args = parser.parse_args()
    try:
        legs = LegLayout.from_formation(FinishedRun(args.run).formation)
    except QdsegaError as exc:  # not a run folder; a legless body
        parser.error(str(exc))
    table = RunFolder(args.run) / RunFolder.TRANSITIONS
    if not table.is_file():
        parser.error(f"{args.run}: no {RunFolder.TRANSITIONS} (not a memo-mode run)")
    swing, lift = np.array(legs.swing), np.array(legs.lift)
    with np.load(table) as data:
        pairs, values = data["pairs"], data["values"]
    before, after = pairs[:, : legs.n_joints], pairs[:, legs.n_joints :]
    print(f"{args.run}: {len(pairs)} transitions, {distinct(before, after)} distinct")

    up_before, up_after = before[:, lift] == 1, after[:, lift] == 1
    for label, moved in (("up before and after", up_before & up_after), ("up before", up_before)):
        canonical = before.copy()
        canonical[:, swing] = np.where(moved, after[:, swing], before[:, swing])
        print(f"  swing ignored for legs {label}: {distinct(canonical, after)} distinct pairs")

    n = len(pairs)
    states = (legs.states(before) - 1) * 4 + (legs.states(after) - 1)
    features = np.zeros((n, legs.n_legs * 16 + 1))
    features[np.arange(n)[:, None], np.arange(legs.n_legs) * 16 + states] = 1.0
    features[:, -1] = 1.0
    failed = values[:, 3] > 0.5
    order = np.random.default_rng(args.seed).permutation(n)
    test, train = order[: int(_HOLDOUT * n)], order[int(_HOLDOUT * n) :]
    fit, held = train[~failed[train]], test[~failed[test]]
    print(f"  failed: {failed.mean():.1%} of the measured transitions")
    for column, label in enumerate(("dx", "dy", "dtheta")):
        weights, *_ = np.linalg.lstsq(features[fit], values[fit, column], rcond=None)
        score = r_squared(values[held, column], features[held] @ weights)
        print(f"  per-leg linear model, held-out R^2 of {label}: {score:.2f}")
    nearest = nearest_rows(pairs[test], pairs[train], _NEIGHBOURS)
    guessed = failed[train][nearest].mean(axis=1) > 0.5
    commoner = max(failed[test].mean(), 1.0 - failed[test].mean())
    print(
        f"  failure from the {_NEIGHBOURS} nearest pairs: {np.mean(guessed == failed[test]):.1%}"
        f" right (the commoner outcome alone: {commoner:.1%})"
    )


if __name__ == "__main__":
    main()
