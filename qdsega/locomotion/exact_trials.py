"""Exact-physics trials in batches: in this process, or spread over worker processes.

A batch is a list of open-loop posture sequences (:meth:`ExactTrials.replays`: reference
gaits), of closed-loop policies (:meth:`ExactTrials.rollouts`: a training run's greedy and
exploring trials) or of posture cycles with their footfalls (:meth:`ExactTrials.cycles`: a
repertoire's gaits). Each worker builds one :class:`~qdsega.locomotion.env.LocomotionEnv`; every
trial starts from the env's settled snapshot, which restores exactly
(``PhysicsSettings.deterministic_pairs``), so a trial's outcome does not depend on the number
of workers or on which worker ran it, and a batch comes back in the order it was given.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from qdsega.agent.policy import Policy, Rollout, SequencePolicy, rollout
from qdsega.description import Formation
from qdsega.locomotion.env import LocomotionEnv, Replay, replay_postures, rules_env
from qdsega.locomotion.env_model import EnvModel
from qdsega.locomotion.rules import ExactRules
from qdsega.workers.pool import Pool, worker_pool


@dataclass(frozen=True)
class CycleTrial:
    """One trial of a posture cycle.

    Attributes:
        rollout: the trial.
        contacts: which units touched the ground at each failure check of the trial,
            (checks, units) bool, units in the formation's order.
    """

    rollout: Rollout
    contacts: np.ndarray


class ExactTrials:
    """Trials of one formation under one set of rules.

    Args:
        formation: the robot.
        rules: the task, the lower agent and the physics.
        workers: processes running trials (1: one env in this process).
    """

    def __init__(self, *, formation: Formation, rules: ExactRules, workers: int) -> None:
        if workers < 1:
            raise ValueError(f"workers must be at least 1, got {workers}")
        self._env: LocomotionEnv | None = None
        self._pool: Pool | None = None
        self.commands = 0
        """Postures commanded in every trial so far (upper-agent steps simulated)."""
        if workers > 1:
            self._pool = worker_pool(workers, _init_worker, (formation, rules))
        else:
            self._env = rules_env(formation, rules)

    def replays(self, postures: Sequence[np.ndarray]) -> list[Replay]:
        """Each posture sequence (steps, J) of level indices played as one trial, in order."""
        if self._env is not None:
            replays = [replay_postures(self._env, p) for p in postures]
        else:
            assert self._pool is not None
            replays = list(self._pool.map(_replay_in_worker, postures))
        self.commands += sum(r.completed + (r.failure is not None) for r in replays)
        return replays

    def rollouts(self, policies: Sequence[Policy], *, steps: int) -> list[Rollout]:
        """Each policy run for one trial of at most ``steps`` commands, in order. A policy that
        draws from a random generator draws from its own copy in a worker (give each its own
        generator)."""
        if self._env is not None:
            world = EnvModel(env=self._env)
            trials = [rollout(policy, world, steps=steps) for policy in policies]
        else:
            assert self._pool is not None
            trials = list(self._pool.map(_rollout_in_worker, policies, [steps] * len(policies)))
        self.commands += sum(len(t.postures) for t in trials)
        return trials

    def cycles(self, cycles: Sequence[np.ndarray], *, steps: int) -> list[CycleTrial]:
        """Each posture cycle (k, J) commanded in turn for one trial of at most ``steps``
        commands, in order, with the trial's footfalls."""
        if self._env is not None:
            trials = [_cycle_trial(self._env, cycle, steps) for cycle in cycles]
        else:
            assert self._pool is not None
            trials = list(self._pool.map(_cycle_in_worker, cycles, [steps] * len(cycles)))
        self.commands += sum(len(t.rollout.postures) for t in trials)
        return trials

    def close(self) -> None:
        if self._pool is not None:
            self._pool.shutdown(cancel_futures=True)
            self._pool = None
        if self._env is not None:
            self._env.close()
            self._env = None

    def __enter__(self) -> ExactTrials:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


_worker_env: LocomotionEnv | None = None


def _init_worker(formation: Formation, rules: ExactRules) -> None:
    global _worker_env
    _worker_env = rules_env(formation, rules)


def _replay_in_worker(postures: np.ndarray) -> Replay:
    assert _worker_env is not None, "worker not initialised"
    return replay_postures(_worker_env, postures)


def _rollout_in_worker(policy: Policy, steps: int) -> Rollout:
    assert _worker_env is not None, "worker not initialised"
    return rollout(policy, EnvModel(env=_worker_env), steps=steps)


def _cycle_in_worker(cycle: np.ndarray, steps: int) -> CycleTrial:
    assert _worker_env is not None, "worker not initialised"
    return _cycle_trial(_worker_env, cycle, steps)


def _cycle_trial(env: LocomotionEnv, cycle: np.ndarray, steps: int) -> CycleTrial:
    played = rollout(SequencePolicy(commands=cycle), EnvModel(env=env), steps=steps)
    return CycleTrial(played, env.contacts())
