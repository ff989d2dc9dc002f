"""Figures of a repertoire (its archive, as points or as heat maps) and of an adaptation
(distance against trials)."""

from __future__ import annotations

import itertools
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


def best_per_square(points: np.ndarray, values: np.ndarray, bins: int) -> np.ndarray:
    """The largest of ``values`` (n,) among the ``points`` (n, 2) in ``[0, 1]^2`` that fall in
    each square of a ``bins`` x ``bins`` grid, NaN where none does; shape (bins, bins), rows the
    second coordinate (a point on an edge counts in the square inside)."""
    squares = np.clip(np.floor(np.asarray(points) * bins + 1e-9), 0, bins - 1).astype(np.int64)
    grid = np.full((bins, bins), np.nan)
    np.fmax.at(grid, (squares[:, 1], squares[:, 0]), np.asarray(values, dtype=np.float64))
    return grid


def archive_heat_map(
    archive: Archive, record: dict[str, Any], file: Path, *, bins: int = 10
) -> Path:
    """The archive as heat maps of its descriptor, two axes at a time: each square is coloured by
    the farthest elite whose two values fall in it (whatever its others), blank where none does.
    A D-dimensional descriptor takes the D (D - 1) / 2 pairs of its axes, one map each."""
    cells = archive.filled
    points, distances = archive.descriptors[cells], archive.fitness[cells]
    names = list(record["descriptor_names"])
    dims = points.shape[1]
    if dims == 1:  # one map: the axis against a constant
        points = np.column_stack([points, np.full(len(points), 0.5)])
        names, dims = [names[0], ""], 2
    side = dims - 1
    size = (1.7 * side + 1.6, 1.7 * side + 0.9)
    fig, axes = plt.subplots(side, side, figsize=size, squeeze=False, layout="constrained")
    shade = plt.get_cmap("viridis").with_extremes(bad="#f0f0f0")
    scale = matplotlib.colors.Normalize(vmin=min(0.0, distances.min()), vmax=distances.max())
    for row, column in itertools.product(range(side), range(side)):
        ax = axes[row, column]
        y, x = row + 1, column
        if x >= y:
            ax.axis("off")
            continue
        grid = best_per_square(points[:, [x, y]], distances, bins)
        ax.imshow(grid, origin="lower", extent=(0, 1, 0, 1), cmap=shade, norm=scale)
        ax.set_xticks([0, 0.5, 1])
        ax.set_yticks([0, 0.5, 1])
        ax.tick_params(labelsize=7, labelbottom=row == side - 1, labelleft=column == 0)
        if row == side - 1:
            ax.set_xlabel(names[x])
        if column == 0:
            ax.set_ylabel(names[y])
    shown = matplotlib.cm.ScalarMappable(norm=scale, cmap=shade)
    fig.colorbar(shown, ax=axes, label="distance on the intact body (m)", shrink=0.7)
    title = f"{record['formation']}: {len(cells)} elites in {len(archive.centroids)} cells"
    fig.suptitle(
        f"{title} ({archive.coverage:.0%})\n{record['descriptor']}; each square: the farthest "
        "elite there",
        fontsize=10,
    )
    fig.savefig(file, dpi=120)
    plt.close(fig)
    return file


def adaptation_curve(result: dict[str, Any], file: Path, *, fresh_m: float | None) -> Path:
    """Each trial's exact distance, the best so far, the model's prediction before it; and the
    fresh QDSEGA result F of the changed body where it is known."""
    trials = result["trials"]
    numbers = np.arange(1, len(trials) + 1)
    distances = np.array([t["distance_m"] for t in trials])
    fig, ax = plt.subplots(figsize=(6, 4))
    where = "on the robot" if result.get("mode") == "external" else "exact physics"
    ax.plot(numbers, distances, "o", label=f"trial ({where})")
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
