"""Figures of a run folder: learning curve, Q-table size, the paper's Fig. 11 (trajectories),
Fig. 12 (gait of a legged body), Fig. 13 (poses of a snake) and the joint angles."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
from matplotlib.ticker import MaxNLocator

from qdsega.errors import RunFolderError
from qdsega.training.run_folder import RunFolder

LEARNING_CURVE = "learning_curve.png"
QTABLE_SIZE = "qtable_size.png"
TRAJECTORIES = "fig11_trajectories.png"
GAIT = "fig12_gait.png"
SNAKE_POSES = "fig13_snake_poses.png"
JOINT_ANGLES = "joint_angles.png"
FIGURES = (LEARNING_CURVE, QTABLE_SIZE, TRAJECTORIES, GAIT, SNAKE_POSES, JOINT_ANGLES)
"""Every figure ``qdsega plot`` can draw; the gait needs legs, the snake poses a legless body
and an evaluation (``qdsega evaluate``)."""


def body_in_world(summary: dict[str, Any]) -> str:
    """A run's body and world, as titles name them (runs from before worlds walked on flat)."""
    return f"{summary['formation']} in {summary.get('world', 'flat')}"


def selected_generations(count: int, shown: int = 6) -> list[int]:
    """About ``shown`` generation numbers from 1 to ``count``, first and last included."""
    return sorted({round(g) for g in np.linspace(1, count, min(shown, count))})


def plot_run(run: Path | str, *, fresh: Path | None = None) -> tuple[list[Path], list[str]]:
    """Draw the run's figures into its folder.

    A warm-started run's learning curve also shows a fresh run's of the same formation:
    ``fresh``, else a finished sibling folder of ``run`` that trained the same formation (same
    content hash) from scratch, the same seed first.

    Returns:
        The figures written, and a note for each figure left out (and why).

    Raises:
        RunFolderError: the folder (or ``fresh``) is not a finished run folder, or its files
            do not parse.
    """
    run = Path(run)
    folder = RunFolder(run)
    folder.require_finished(folder.TRAJECTORIES, folder.METRICS)
    summary, evaluation = folder.read_summary(), folder.read_evaluation()
    try:
        with np.load(folder / folder.TRAJECTORIES) as data:
            poses, legs, names = data["exact_poses"], data["gait_legs"], data["leg_names"]
            light, angles, joints = data["light"], data["gait_angles_deg"], data["joint_names"]
    except (OSError, ValueError, KeyError) as exc:
        raise RunFolderError(f"corrupt run folder ({exc})", file=run) from None
    metrics = folder.read_metrics()
    notes = []
    baseline = None
    if summary.get("warm_start") is not None:
        fresh = fresh or fresh_sibling(run, summary)
        if fresh is None:
            notes.append(f"{LEARNING_CURVE}: no fresh run of {summary['formation']} beside it")
        else:
            RunFolder(fresh).require_finished(RunFolder.METRICS)
            baseline = (fresh, RunFolder(fresh).read_metrics())
    paths = [
        _learning_curve(run / LEARNING_CURVE, metrics, summary, evaluation, baseline),
        _qtable_size(run / QTABLE_SIZE, metrics),
        _trajectories(run / TRAJECTORIES, poses, light),
    ]
    if legs.shape[1] > 0:
        paths.append(_gait(run / GAIT, legs, names))
    elif evaluation is not None and "unit_xy_m" in evaluation:
        paths.append(_snake_poses(run / SNAKE_POSES, np.array(evaluation["unit_xy_m"]), light))
    else:
        notes.append(f"{SNAKE_POSES} needs an evaluation: run qdsega evaluate {run} first")
    paths.append(_joint_angles(run / JOINT_ANGLES, angles, joints))
    return paths, notes


def fresh_sibling(run: Path, summary: dict[str, Any]) -> Path | None:
    """A finished folder beside ``run`` that trained the same formation (content hash) with
    the same world from scratch; the same seed first, then by name; None if there is none."""
    found = []
    for folder in sorted(run.resolve().parent.iterdir()):
        if folder == run.resolve() or not RunFolder(folder).finished:
            continue
        try:
            other = RunFolder(folder).read_summary()
        except RunFolderError:
            continue
        if (
            other.get("warm_start") is None
            and other.get("formation_sha256") == summary.get("formation_sha256")
            and other.get("sim") == summary.get("sim")
        ):
            found.append((other.get("seed") != summary.get("seed"), folder))
    return min(found)[1] if found else None


def _learning_curve(
    path: Path,
    metrics: dict[str, np.ndarray],
    summary: dict[str, Any],
    evaluation: dict[str, Any] | None,
    fresh: tuple[Path, dict[str, np.ndarray]] | None = None,
) -> Path:
    """Each generation's greedy policy with exact physics (and, where the learner's model is a
    measured table, the table's prediction), against the optimum (MSM) or the reference; for a
    warm-started run, against a fresh run's exact curve and 0.9 of its result (its farthest
    exact generation), with the verified distance of the path it was handed at generation 0."""
    generation = metrics["generation"]
    fig, ax = plt.subplots(figsize=(7, 5.2))
    exact = "MSM" if summary["sim"] == "msm" else "PyBullet, every step simulated"
    warm = summary.get("warm_start")
    started = "" if warm is None else f", warm-started from {warm['formation']}"
    ax.plot(
        generation,
        metrics["greedy_exact_m"],
        "-o",
        markersize=3,
        label=f"greedy policy ({exact}){started}",
    )
    if warm is not None and warm.get("handed_on_m") is not None:
        ax.plot(
            [0],
            [warm["handed_on_m"]],
            "D",
            color="tab:blue",
            label="the old run's best path on this body (generation 0: before learning)",
        )
    if fresh is not None:
        folder, other = fresh
        ax.plot(
            other["generation"],
            other["greedy_exact_m"],
            "-s",
            markersize=3,
            color="tab:green",
            label=f"fresh run from scratch ({folder.name})",
        )
        ax.axhline(
            0.9 * other["greedy_exact_m"].max(),  # the fresh run's result
            color="tab:green",
            linestyle=":",
            label="0.9 of the fresh run's result",
        )
    if summary["sim"] == "memo":
        ax.plot(
            generation,
            metrics["greedy_distance_m"],
            "--",
            color="tab:gray",
            linewidth=1,
            label="greedy policy as the memo table predicts it",
        )
    if summary.get("optimum") is not None:
        ax.axhline(summary["optimum"], color="k", linestyle="--", label="optimum (MSM)")
    if evaluation is not None:
        reference = evaluation["reference"]
        ax.axhline(
            reference["distance_m"],
            color="tab:red",
            linestyle="--",
            label=f"reference: {reference['kind']} (PyBullet)",
        )
    ax.set_xlabel("generation")
    ax.xaxis.set_major_locator(MaxNLocator(integer=True))
    ax.set_ylabel("distance toward the light (m)")
    ax.set_title(f"{body_in_world(summary)}: learning curve")
    # Below the axes: inside, it hid the curves and the 0.9 line (the figure grows to fit).
    ax.legend(fontsize=8, loc="upper left", bbox_to_anchor=(0, -0.16))
    ax.grid(alpha=0.3)
    return save_figure(fig, path)


def _qtable_size(path: Path, metrics: dict[str, np.ndarray]) -> Path:
    """Actions, interior states and Q-table entries per generation."""
    generation = metrics["generation"]
    fig, (top, bottom) = plt.subplots(2, 1, figsize=(7, 4.2), sharex=True)
    top.plot(generation, metrics["actions"], "-o", markersize=3, label="actions")
    top.plot(generation, metrics["interior_states"], "-s", markersize=3, label="interior states")
    top.set_ylabel("count")
    top.legend(fontsize=8)
    top.grid(alpha=0.3)
    bottom.plot(generation, metrics["q_entries"], "-o", markersize=3, color="tab:purple")
    bottom.set_ylabel("Q-table entries")
    bottom.set_xlabel("generation")
    bottom.xaxis.set_major_locator(MaxNLocator(integer=True))
    bottom.grid(alpha=0.3)
    fig.suptitle("Exploration space per generation (states include the exterior bins)")
    return save_figure(fig, path)


def _snake_poses(path: Path, units: np.ndarray, light: np.ndarray) -> Path:
    """Fig. 13: the body seen from above at successive steps of the exact replay.

    Args:
        units: every unit's centre (x, y) (m) at the start and after each step,
            shape (steps + 1, U, 2).
    """
    shown = sorted({round(t) for t in np.linspace(0, len(units) - 1, min(7, len(units)))})
    low, high = units.reshape(-1, 2).min(axis=0), units.reshape(-1, 2).max(axis=0)
    margin = 0.03 + 0.05 * float(np.max(high - low))
    span = high - low + 2 * margin
    width = 7.0
    row = max(0.6, 0.8 * width * span[1] / span[0])
    fig, axes = plt.subplots(len(shown), 1, figsize=(width, row * len(shown) + 1.0), sharex=True)
    axes = np.atleast_1d(axes)
    direction = light / max(float(np.hypot(*light)), 1e-12)
    for ax, t in zip(axes, shown, strict=True):
        ax.plot(*units[: t + 1, 0].T, ":", color="0.6", linewidth=1)
        ax.plot(*units[t].T, "-o", color="tab:blue", markersize=3, linewidth=2)
        ax.plot(*units[t, 0], "o", color="tab:red", markersize=4)
        ax.annotate(
            "",
            xy=tuple(low + 0.15 * span[0] * direction),
            xytext=tuple(low),
            arrowprops={"arrowstyle": "->", "color": "orange"},
        )
        ax.set_xlim(low[0] - margin, high[0] + margin)
        ax.set_ylim(low[1] - margin, high[1] + margin)
        ax.set_aspect("equal")
        ax.text(0.01, 0.9, f"step {t}", transform=ax.transAxes, fontsize=8, va="top")
        ax.tick_params(labelsize=7)
    axes[-1].set_xlabel("x (m)")
    fig.suptitle(
        "Snake seen from above, replayed in PyBullet\n(red: head, dotted: its path, arrow: light)"
    )
    return save_figure(fig, path)


def _trajectories(path: Path, poses: np.ndarray, light: np.ndarray) -> Path:
    """Fig. 11: the greedy trial's path at selected generations, one row each."""
    generations = selected_generations(len(poses))
    fig, axes = plt.subplots(
        len(generations), 1, figsize=(7, 1.1 * len(generations) + 0.8), sharex=True
    )
    axes = np.atleast_1d(axes)
    reach = max(float(np.max(np.abs(poses[..., :2]))), 1e-3)
    direction = light / max(float(np.hypot(*light)), 1e-12)
    for ax, g in zip(axes, generations, strict=True):
        xy = poses[g - 1, :, :2]
        ax.plot(xy[:, 0], xy[:, 1], "-o", markersize=2, linewidth=1)
        ax.annotate(
            "",
            xy=tuple(0.3 * reach * direction),
            xytext=(0, 0),
            arrowprops={"arrowstyle": "->", "color": "orange"},
        )
        ax.set_ylabel(str(g), rotation=0, labelpad=15)
        ax.set_ylim(-reach * 0.6, reach * 0.6)
    axes[-1].set_xlabel("x (m)")
    fig.suptitle("Greedy policy per generation, exact physics (arrow: toward the light)")
    return save_figure(fig, path)


def _gait(path: Path, legs: np.ndarray, names: np.ndarray) -> Path:
    """Fig. 12: each leg's state (1-4) at each step of the result's exact trial."""
    fig, ax = plt.subplots(figsize=(max(6, 0.35 * len(legs) + 2), 0.35 * legs.shape[1] + 1.5))
    cmap = matplotlib.colors.ListedColormap(["#1b7837", "#a6dba0", "#c2a5cf", "#762a83"])
    ax.imshow(legs.T, aspect="auto", cmap=cmap, vmin=0.5, vmax=4.5, interpolation="nearest")
    for (t, leg), state in np.ndenumerate(legs):
        ax.text(t, leg, str(state), ha="center", va="center", fontsize=7)
    ax.set_yticks(range(len(names)), [str(n) for n in names])
    ax.set_xlabel("step (0: initial posture)")
    ax.set_title("Acquired gait: 1 fwd+down, 2 back+down, 3 fwd+up, 4 back+up")
    return save_figure(fig, path)


def _joint_angles(path: Path, angles: np.ndarray, names: np.ndarray) -> Path:
    """Commanded joint angles of the result's exact trial, one line per joint, stacked."""
    count = angles.shape[1]
    spacing = max(float(np.ptp(angles)) if angles.size else 0.0, 1.0) * 1.2
    fig, ax = plt.subplots(figsize=(7, 0.45 * count + 1.5))
    steps = np.arange(len(angles))
    for k in range(count):
        ax.step(steps, angles[:, k] - k * spacing, where="post", linewidth=1.2)
    ax.set_yticks([-k * spacing for k in range(count)], [str(n) for n in names])
    ax.set_xlabel("step (0: initial posture)")
    ax.set_title(f"Joint angles of the acquired motion (each line spans {spacing:.0f} deg)")
    return save_figure(fig, path)


def save_figure(fig: matplotlib.figure.Figure, path: Path) -> Path:
    """Lay out, write at 120 dpi and close ``fig``; return ``path``."""
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return path
