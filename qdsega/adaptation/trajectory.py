"""A gait as a robot plays it: joint angles over time, one CSV file a trial.

``qdsega adapt --external`` writes every gait to try this way, and ``--blind`` plays the same
file on a hidden body (:mod:`qdsega.adaptation.hidden_body`). The header is ``time_s`` and then
the actuated joints, named as in the formation; a row is one command of the lower agent: from
``time_s`` (s) on, drive every joint toward its angle (rad) at the joint speed (a posture a
step, :mod:`qdsega.locomotion.lower_agent`). The last row repeats the last command at the
trial's end, where the distance is measured.
"""

from __future__ import annotations

import csv
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from qdsega.atomic import replaced_atomically
from qdsega.description import Formation
from qdsega.errors import RunFolderError
from qdsega.locomotion.rules import ExactRules
from qdsega.training.joint_mapping import nearest_levels

TIME = "time_s"
"""The time column's name."""
TIME_DECIMALS = 9
"""A command's time is rounded to this many decimals (s), so that it reads back as written."""


@dataclass(frozen=True)
class JointTrajectory:
    """Joint targets over time.

    Attributes:
        joints: the joints' names, a column each.
        times_s: when each command starts, the trial's end last, strictly increasing (n + 1,).
        angles_rad: each command's joint targets, the last repeated at the end (n + 1, J).
    """

    joints: tuple[str, ...]
    times_s: np.ndarray
    angles_rad: np.ndarray

    def __post_init__(self) -> None:
        times, angles = np.asarray(self.times_s, float), np.asarray(self.angles_rad, float)
        if times.ndim != 1 or len(times) < 2 or angles.shape != (len(times), len(self.joints)):
            message = f"{len(self.joints)} joints, times {times.shape}, angles {angles.shape}"
            raise ValueError(f"need 2+ rows of a time and an angle a joint, got {message}")
        if not (np.all(np.isfinite(times)) and np.all(np.isfinite(angles))):
            raise ValueError("times and angles must be finite")
        if np.any(np.diff(times) <= 0):
            raise ValueError("times must increase strictly")
        object.__setattr__(self, "times_s", times)
        object.__setattr__(self, "angles_rad", angles)

    @classmethod
    def of(cls, formation: Formation, commands: np.ndarray, step_s: float) -> JointTrajectory:
        """Postures ``commands`` (n, J) of ``formation``'s level indices, one every ``step_s``
        seconds from 0."""
        angles = np.array([formation.posture_rad(p) for p in np.asarray(commands)], float)
        times = np.round(np.arange(len(angles) + 1) * step_s, TIME_DECIMALS)
        return cls(
            joints=tuple(j.name for j in formation.joints),
            times_s=times,
            angles_rad=np.vstack([angles, angles[-1:]]),
        )

    @classmethod
    def trial(cls, formation: Formation, cycle: np.ndarray, rules: ExactRules) -> JointTrajectory:
        """One trial of ``rules`` of the posture cycle ``cycle`` (k, J), repeated for
        ``rules.task.trial_steps`` commands at the lower agent's step."""
        cycle = np.asarray(cycle)
        commands = np.resize(cycle, (rules.task.trial_steps, cycle.shape[1]))
        return cls.of(formation, commands, rules.lower_agent.step_duration_for(formation))

    @property
    def commands_rad(self) -> np.ndarray:
        """The commands' joint targets, without the end's row (n, J)."""
        return self.angles_rad[:-1]

    def levels_on(self, body: Formation) -> np.ndarray:
        """The commands as ``body``'s postures (n, J_body): each of its joints that the
        trajectory names at the level nearest the angle sent to it, the others at rest. A
        column ``body`` lacks (a lost or locked joint) reaches nothing."""
        rest = np.array(body.rest_levels(), dtype=np.int64)
        postures = np.tile(rest, (len(self.commands_rad), 1))
        column = {name: k for k, name in enumerate(self.joints)}
        for j, joint in enumerate(body.joints):
            if joint.name in column:
                angles = self.commands_rad[:, column[joint.name]]
                postures[:, j] = nearest_levels(joint.levels_rad, angles)
        return postures

    def write(self, path: Path) -> None:
        """Write the CSV at ``path``, atomically (a reader never sees half of it)."""
        path.parent.mkdir(parents=True, exist_ok=True)
        with replaced_atomically(path) as partial, partial.open("w", newline="") as stream:
            writer = csv.writer(stream, lineterminator="\n")
            writer.writerow([TIME, *self.joints])
            for time, angles in zip(self.times_s, self.angles_rad, strict=True):
                writer.writerow([repr(float(time)), *(repr(float(a)) for a in angles)])

    @classmethod
    def read(cls, path: Path) -> JointTrajectory:
        """The trajectory in the CSV at ``path``.

        Raises:
            RunFolderError: no such file, or not a trajectory.
        """
        try:
            with path.open(newline="") as stream:
                rows = list(csv.reader(stream))
            if not rows or rows[0][:1] != [TIME]:
                raise ValueError(f"the header must start with {TIME}")
            values = np.array(rows[1:], dtype=np.float64)
            return cls(joints=tuple(rows[0][1:]), times_s=values[:, 0], angles_rad=values[:, 1:])
        except (OSError, ValueError, IndexError) as exc:
            raise RunFolderError(f"not a joint trajectory ({exc})", file=path) from None

    def same_as(self, other: JointTrajectory) -> bool:
        """Whether ``other`` commands the same joints to the same angles at the same times."""
        return (
            self.joints == other.joints
            and np.array_equal(self.times_s, other.times_s)
            and np.array_equal(self.angles_rad, other.angles_rad)
        )
