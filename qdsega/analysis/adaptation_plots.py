"""Figures of a repertoire (its archive) and of an adaptation (distance against trials)."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
from matplotlib.ticker import MaxNLocator

from qdsega.adaptation.archive import Archive
from qdsega.analysis.plots import save_figure


def archive_map(archive: Archive, record: dict[str, Any], file: Path) -> Path:
    """Each elite at its descriptor, coloured by its distance: the two descriptors as they are,
    or for more, their first two principal components."""
    cells = archive.filled
    points, names = archive.descriptors[cells], list(record["descriptor_names"])
    if points.shape[1] > 2 and len(points) >= 2:
        centred = points - points.mean(axis=0)
        _, _, axes = np.linalg.svd(centred, full_matrices=False)
        points, names = centred @ axes[:2].T, ["first principal axis", "second principal axis"]
    elif points.shape[1] == 1:
        points, names = np.column_stack([points[:, 0], np.zeros(len(points))]), [names[0], ""]
    fig, ax = plt.subplots(figsize=(5.5, 4.5))
    shown = ax.scatter(points[:, 0], points[:, 1], c=archive.fitness[cells], cmap="viridis", s=30)
    fig.colorbar(shown, ax=ax, label="distance on the intact body (m)")
    ax.set_xlabel(names[0])
    ax.set_ylabel(names[1])
    title = f"{record['formation']}: {len(cells)} elites ({archive.coverage:.0%} of cells)"
    ax.set_title(f"{title}\n{record['descriptor']}")
    return save_figure(fig, file)


def adaptation_curve(result: dict[str, Any], file: Path, *, fresh_m: float | None) -> Path:
    """Each trial's exact distance, the best so far, the model's prediction before it; and the
    fresh QDSEGA result F of the changed body where it is known."""
    trials = result["trials"]
    numbers = np.arange(1, len(trials) + 1)
    distances = np.array([t["distance_m"] for t in trials])
    fig, ax = plt.subplots(figsize=(6, 4))
    ax.plot(numbers, distances, "o", label="trial (exact physics)")
    ax.step(numbers, np.maximum.accumulate(distances), where="post", label="best so far")
    ax.plot(numbers, [t["predicted_m"] for t in trials], "x", label="predicted before the trial")
    if fresh_m is not None:
        fresh = f"fresh QDSEGA run F = {fresh_m:.3f} m"
        ax.axhline(fresh_m, color="k", linestyle="--", label=fresh)
        ax.axhline(0.8 * fresh_m, color="grey", linestyle=":", label="0.8 F")
    ax.set_xlabel("trial")
    ax.xaxis.set_major_locator(MaxNLocator(integer=True))
    ax.set_ylabel("distance toward the light (m)")
    ax.set_title(f"{result['formation']}: adaptation with {result['intact']}'s repertoire")
    ax.legend(fontsize=8)
    return save_figure(fig, file)
