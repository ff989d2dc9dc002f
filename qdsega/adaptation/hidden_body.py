"""A changed body standing in for a robot whose change the search does not know (``qdsega adapt
--blind``), as Intelligent Trial and Error meets a damaged robot (Cully et al. 2015).

It plays the intact body's joint angles over time (:class:`~qdsega.adaptation.trajectory.
JointTrajectory`, what ``--external`` hands a robot) in exact physics, at their timing: a
command sent to a joint the body lost, or to a locked one, reaches nothing; a joint the
commands do not name holds its rest level. Its trial is judged by the body's own lower agent
(its joints, its trunk) and the task of the repertoire's world, as a mapped trial is.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from qdsega.adaptation.trajectory import JointTrajectory
from qdsega.agent.policy import Rollout, SequencePolicy
from qdsega.description import Formation, World
from qdsega.errors import FormationError
from qdsega.locomotion.exact_trials import ExactTrials
from qdsega.training.config import resolve_config

STEP_TOLERANCE_S = 1e-6
"""How far a command's time may be from the step's multiple (s)."""


class HiddenBody:
    """Exact-physics trials of ``body`` in ``world`` that play joint trajectories of
    ``commands`` commands, one every ``step_s`` seconds.

    Raises:
        FormationError: ``body`` cannot cross its joints' levels within ``step_s``.
    """

    def __init__(self, *, body: Formation, world: World, step_s: float, commands: int) -> None:
        self.body = world.lights(body)
        own = resolve_config(overrides={"sim": "memo"}, formation=self.body).rules(world)
        self.rules = replace(
            own,
            task=replace(own.task, trial_steps=commands),
            lower_agent=replace(own.lower_agent, step_duration_s=step_s),
        )
        sweep, joint = self.rules.lower_agent.sweep_s(self.body)
        if sweep > step_s:
            message = (
                f"joint {joint} needs {sweep:.2f} s to cross its levels, more than the "
                f"commands' step of {step_s} s"
            )
            raise FormationError(message, file=body.file)
        self.step_s = step_s
        self._trials = ExactTrials(formation=self.body, rules=self.rules, workers=1)

    def play(self, trajectory: JointTrajectory) -> Rollout:
        """One trial of ``trajectory``, from the body's rest posture.

        Raises:
            ValueError: not ``commands`` commands, one every ``step_s`` seconds from 0.
        """
        steps = self.rules.task.trial_steps
        expected = np.arange(steps + 1) * self.step_s
        if trajectory.times_s.shape != expected.shape or not np.allclose(
            trajectory.times_s, expected, rtol=0.0, atol=STEP_TOLERANCE_S
        ):
            message = f"expected {steps} commands, one every {self.step_s} s from 0"
            raise ValueError(message)
        postures = trajectory.levels_on(self.body)
        (trial,) = self._trials.rollouts([SequencePolicy(commands=postures)], steps=steps)
        return trial

    def close(self) -> None:
        self._trials.close()

    def __enter__(self) -> HiddenBody:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()
