"""Hand-designed gaits to measure learnt ones against, as posture sequences (level indices).

* Snakes: the serpenoid travelling wave (Hirose), ``theta_i(k) = A sin(2 pi k / N - i phi)`` for
  joint ``i`` (head first) at step ``k``, snapped to the nearest level of each joint.
* Legged bodies: the classic gaits in the paper's four leg states (1 forward+down, 2 back+down,
  3 forward+up, 4 back+up). Each leg cycles 1 -> 2 (stroke) -> 4 (lift) -> 3 (swing forward)
  -> 1 (land); gaits differ in the phase of each leg:

  - ``alternating`` (tripod for six legs): neighbours along a side and the two legs of a pair
    are half a cycle apart;
  - ``wave``: a phase that travels from the back leg to the front leg, a quarter cycle per leg;
  - ``pairs``: both legs of a pair together, neighbouring pairs half a cycle apart.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Iterator
from typing import Any

import numpy as np

from qdsega.description import Formation
from qdsega.description.formation import Side

LEG_CYCLE = (1, 2, 4, 3)
"""A leg's state sequence: land forward, stroke back, lift, swing forward."""


def serpenoid(
    formation: Formation,
    *,
    amplitude_rad: float,
    phase_lag_rad: float,
    steps_per_cycle: int,
    steps: int,
) -> np.ndarray:
    """Travelling wave from head to tail, snapped to levels, shape (steps, J)."""
    if steps_per_cycle < 2:
        raise ValueError(f"steps_per_cycle must be at least 2, got {steps_per_cycle}")
    rows = []
    for k in range(1, steps + 1):
        row = []
        for i, joint in enumerate(formation.joints):
            angle = amplitude_rad * math.sin(2 * math.pi * k / steps_per_cycle - i * phase_lag_rad)
            levels = np.asarray(joint.levels_rad)
            row.append(int(np.argmin(np.abs(levels - angle))))
        rows.append(row)
    return np.array(rows, dtype=np.int64)


def serpenoid_grid(
    formation: Formation, *, steps: int
) -> Iterator[tuple[dict[str, Any], np.ndarray]]:
    """Serpenoid candidates over amplitude, phase lag and steps per cycle, with parameters."""
    widest = max(max(abs(a) for a in j.levels_rad) for j in formation.joints)
    amplitudes = [widest * f for f in (0.5, 0.75, 1.0)]
    lags = [math.radians(d) for d in (30, 45, 60, 90, 120)]
    cycles = [4, 6, 8]
    for amplitude, lag, cycle in itertools.product(amplitudes, lags, cycles):
        params = {
            "amplitude_deg": math.degrees(amplitude),
            "phase_lag_deg": math.degrees(lag),
            "steps_per_cycle": cycle,
        }
        yield (
            params,
            serpenoid(
                formation,
                amplitude_rad=amplitude,
                phase_lag_rad=lag,
                steps_per_cycle=cycle,
                steps=steps,
            ),
        )


def leg_gait(formation: Formation, *, gait: str, steps: int) -> np.ndarray:
    """A classic gait as postures, shape (steps, J); non-leg joints keep their rest level."""
    if not formation.legs:
        raise ValueError(f"{formation.name} has no legs")
    phases = _phases(formation, gait)
    rest = np.array(formation.rest_levels(), dtype=np.int64)
    rows = []
    for k in range(1, steps + 1):
        row = rest.copy()
        for leg in formation.legs:
            state = LEG_CYCLE[(k + phases[leg.name]) % len(LEG_CYCLE)]
            row[formation.joint_index(leg.swing_joint)] = (state - 1) % 2
            row[formation.joint_index(leg.lift_joint)] = (state - 1) // 2
        rows.append(row)
    return np.array(rows, dtype=np.int64)


LEG_GAITS = ("alternating", "wave", "pairs")


def _phases(formation: Formation, gait: str) -> dict[str, int]:
    """Phase offset (steps of the 4-step cycle) of every leg."""
    phases = {}
    offsets: tuple[tuple[int, Side], ...] = ((0, "left"), (2, "right"))
    for side_offset, side in offsets:
        legs = formation.legs_on(side)
        for position, leg in enumerate(legs):
            if gait == "alternating":
                phases[leg.name] = (2 * position + side_offset) % 4
            elif gait == "wave":
                phases[leg.name] = (len(legs) - 1 - position + side_offset) % 4
            elif gait == "pairs":
                phases[leg.name] = (2 * position) % 4
            else:
                raise ValueError(f"unknown gait {gait!r}; choose from {', '.join(LEG_GAITS)}")
    return phases


def default_gait(formation: Formation, *, steps: int) -> np.ndarray:
    """A sensible scripted gait for any formation, shape (steps, J): the wave gait for a legged
    body, else a serpenoid wave (20 deg, 60 deg lag, 4 steps a cycle, capped at the levels)."""
    if formation.legs:
        return leg_gait(formation, gait="wave", steps=steps)
    return serpenoid(
        formation,
        amplitude_rad=math.radians(20),
        phase_lag_rad=math.radians(60),
        steps_per_cycle=4,
        steps=steps,
    )
