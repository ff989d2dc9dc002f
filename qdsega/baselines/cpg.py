"""A central pattern generator (CPG) gait for any formation: one sine oscillator per joint.

Joint ``j`` at upper-agent step ``k`` (k = 1, 2, ...) is commanded the level nearest to

    offset_j + amplitude_j * sin(2 pi k / P + phase_j)

(the first of equally near levels, as :func:`qdsega.locomotion.classic_gaits.serpenoid`
snaps), so the posture sequence repeats every ``P`` steps. Nothing is specific to a body: a
snake's yaw joints with nine levels and a leg's swing and lift joints with two levels are
driven alike; with two levels the oscillator becomes a square wave whose duty cycle the offset
sets.

:meth:`CPGGait.from_unit` maps a point of the unit box ``[0, 1]^(3J)`` onto gaits whose
offsets lie within each joint's level range and whose amplitudes reach across it, for searches
that want one scale for all parameters (:mod:`qdsega.baselines.reference_search`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from qdsega.description import Formation


@dataclass(frozen=True, kw_only=True)
class CPGGait:
    """One sine oscillator per joint, all with one period.

    Attributes:
        amplitude_rad: amplitude of each joint, shape (J,) (rad), non-negative.
        offset_rad: centre angle of each joint, shape (J,) (rad).
        phase_rad: phase of each joint, shape (J,) (rad).
        period_steps: period P of every oscillator (upper-agent steps), at least 2.
    """

    amplitude_rad: tuple[float, ...]
    offset_rad: tuple[float, ...]
    phase_rad: tuple[float, ...]
    period_steps: int

    def __post_init__(self) -> None:
        n = len(self.amplitude_rad)
        if n == 0 or len(self.offset_rad) != n or len(self.phase_rad) != n:
            raise ValueError(
                "amplitude_rad, offset_rad and phase_rad must have one value per joint, got "
                f"{n}, {len(self.offset_rad)} and {len(self.phase_rad)}"
            )
        values = (*self.amplitude_rad, *self.offset_rad, *self.phase_rad)
        if not all(math.isfinite(v) for v in values):
            raise ValueError("CPG parameters must be finite")
        if min(self.amplitude_rad) < 0:
            raise ValueError(f"amplitudes must be non-negative, got {self.amplitude_rad}")
        if isinstance(self.period_steps, bool) or not isinstance(self.period_steps, int):
            raise ValueError(f"period_steps must be an integer, got {self.period_steps!r}")
        if self.period_steps < 2:
            raise ValueError(f"period_steps must be at least 2, got {self.period_steps}")

    @classmethod
    def from_unit(cls, formation: Formation, unit: np.ndarray, *, period_steps: int) -> CPGGait:
        """The gait at ``unit``, shape (3J,), values in [0, 1]: offsets, amplitudes, phases.

        For joint ``j`` with levels spanning ``[lo, hi]`` (rad): ``offset = lo + u (hi - lo)``,
        ``amplitude = u (hi - lo)`` and ``phase = 2 pi u``. Angles beyond ``[lo, hi]`` snap to
        the extreme level, so large amplitudes give square waves.
        """
        n = len(formation.joints)
        unit = np.asarray(unit, dtype=np.float64)
        if unit.shape != (3 * n,):
            raise ValueError(f"{formation.name} needs {3 * n} unit coordinates, got {unit.shape}")
        if not np.all((unit >= 0) & (unit <= 1)):
            raise ValueError(f"unit coordinates must lie in [0, 1], got {unit}")
        lo = np.array([min(j.levels_rad) for j in formation.joints])
        hi = np.array([max(j.levels_rad) for j in formation.joints])
        offset = lo + unit[:n] * (hi - lo)
        amplitude = unit[n : 2 * n] * (hi - lo)
        phase = 2 * math.pi * unit[2 * n :]
        return cls(
            amplitude_rad=tuple(map(float, amplitude)),
            offset_rad=tuple(map(float, offset)),
            phase_rad=tuple(map(float, phase)),
            period_steps=period_steps,
        )

    def angles_rad(self, *, steps: int) -> np.ndarray:
        """Unsnapped joint angles at steps 1..``steps``, shape (steps, J) (rad)."""
        if steps < 1:
            raise ValueError(f"steps must be at least 1, got {steps}")
        # k mod P keeps the sequence exactly periodic in floating point.
        k = (np.arange(1, steps + 1) % self.period_steps)[:, None]
        wave = np.sin(2 * math.pi * k / self.period_steps + np.array(self.phase_rad))
        return np.array(self.offset_rad) + np.array(self.amplitude_rad) * wave

    def postures(self, formation: Formation, *, steps: int) -> np.ndarray:
        """Level indices at steps 1..``steps``, shape (steps, J): each angle snapped to the
        nearest level of its joint."""
        if len(formation.joints) != len(self.offset_rad):
            raise ValueError(
                f"{formation.name} has {len(formation.joints)} joints, the gait "
                f"{len(self.offset_rad)}"
            )
        joints = formation.joints
        levels = np.full((len(joints), max(len(j.levels_rad) for j in joints)), np.inf)
        for j, joint in enumerate(joints):  # padded with levels no angle is near
            levels[j, : len(joint.levels_rad)] = joint.levels_rad
        angles = self.angles_rad(steps=steps)
        return np.argmin(np.abs(levels[None] - angles[:, :, None]), axis=2).astype(np.int64)

    def to_dict(self) -> dict[str, Any]:
        """Plain types, for JSON."""
        return {
            "amplitude_rad": list(self.amplitude_rad),
            "offset_rad": list(self.offset_rad),
            "phase_rad": list(self.phase_rad),
            "period_steps": self.period_steps,
        }

    @classmethod
    def from_dict(cls, data: dict[str, Any]) -> CPGGait:
        """The gait :meth:`to_dict` wrote.

        Raises:
            ValueError: missing or unknown keys, or bad values.
        """
        keys = {"amplitude_rad", "offset_rad", "phase_rad", "period_steps"}
        if not isinstance(data, dict) or set(data) != keys:
            raise ValueError(f"a CPG gait needs exactly the keys {sorted(keys)}")
        try:
            return cls(
                amplitude_rad=tuple(float(v) for v in data["amplitude_rad"]),
                offset_rad=tuple(float(v) for v in data["offset_rad"]),
                phase_rad=tuple(float(v) for v in data["phase_rad"]),
                period_steps=data["period_steps"],
            )
        except TypeError as exc:
            raise ValueError(f"bad CPG parameters: {exc}") from None
