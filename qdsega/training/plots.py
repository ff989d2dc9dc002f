"""Figures of a run folder, after the paper's Fig. 11 (trajectories) and Fig. 12 (gait)."""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

from qdsega.errors import FormationError

FIGURES = ("fig11_trajectories.png", "fig12_gait.png", "joint_angles.png")
"""Trajectories, the legs' gait (legged formations only) and the joint angles."""


def selected_generations(count: int, shown: int = 6) -> list[int]:
    """About ``shown`` generation numbers from 1 to ``count``, first and last included."""
    return sorted({round(g) for g in np.linspace(1, count, min(shown, count))})


def plot_run(run: Path | str) -> list[Path]:
    """Write the two figures into the run folder; return their paths.

    Raises:
        FormationError: the folder is not a complete run folder.
    """
    run = Path(run)
    source = run / "trajectories.npz"
    if not source.is_file():
        raise FormationError("not a run folder (no trajectories.npz)", file=run)
    try:
        with np.load(source) as data:
            poses, legs, names = data["poses"], data["gait_legs"], data["leg_names"]
            light, angles, joints = data["light"], data["gait_angles_deg"], data["joint_names"]
    except (OSError, ValueError, KeyError) as exc:
        raise FormationError(f"corrupt trajectories.npz ({exc})", file=run) from None
    paths = [_trajectories(run / FIGURES[0], poses, light)]
    if legs.shape[1] > 0:
        paths.append(_gait(run / FIGURES[1], legs, names))
    paths.append(_joint_angles(run / FIGURES[2], angles, joints))
    return paths


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
    fig.suptitle("Greedy trial per generation (arrow: toward the light)")
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return path


def _gait(path: Path, legs: np.ndarray, names: np.ndarray) -> Path:
    """Fig. 12: each leg's state (1-4) at each step of the final greedy trial."""
    fig, ax = plt.subplots(figsize=(max(6, 0.35 * len(legs) + 2), 0.35 * legs.shape[1] + 1.5))
    cmap = matplotlib.colors.ListedColormap(["#1b7837", "#a6dba0", "#c2a5cf", "#762a83"])
    ax.imshow(legs.T, aspect="auto", cmap=cmap, vmin=0.5, vmax=4.5, interpolation="nearest")
    for (t, leg), state in np.ndenumerate(legs):
        ax.text(t, leg, str(state), ha="center", va="center", fontsize=7)
    ax.set_yticks(range(len(names)), [str(n) for n in names])
    ax.set_xlabel("step (0: initial posture)")
    ax.set_title("Acquired gait: 1 fwd+down, 2 back+down, 3 fwd+up, 4 back+up")
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return path


def _joint_angles(path: Path, angles: np.ndarray, names: np.ndarray) -> Path:
    """Commanded joint angles of the final greedy trial, one line per joint, stacked."""
    count = angles.shape[1]
    spacing = max(float(np.ptp(angles)) if angles.size else 0.0, 1.0) * 1.2
    fig, ax = plt.subplots(figsize=(7, 0.45 * count + 1.5))
    steps = np.arange(len(angles))
    for k in range(count):
        ax.step(steps, angles[:, k] - k * spacing, where="post", linewidth=1.2)
    ax.set_yticks([-k * spacing for k in range(count)], [str(n) for n in names])
    ax.set_xlabel("step (0: initial posture)")
    ax.set_title(f"Joint angles of the acquired motion (each line spans {spacing:.0f} deg)")
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return path
