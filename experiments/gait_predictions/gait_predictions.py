"""How well posture tables predict periodic gaits of a formation, against exact physics.

Usage: .venv/bin/python experiments/gait_predictions/gait_predictions.py [FORMATION]
           [--gaits 24] [--seed 0] [--cycles 5]

For the formation's CMA-ES reference gait (shipped or cached, else searched first) and random
gaits of 2 to 4 postures, each repeated for a trial under the ``paper-snake`` preset's rules,
prints the distance covered with exact physics and as three tables predict it, each move
looked up and chained as the learner's table model chains them:

* settled: the memo table (each move from a settled start, :mod:`qdsega.locomotion.memo`);
* after h: each move ``i -> j`` measured right after ``h -> i`` (``h`` reached from rest and
  settled, ``i`` not), keyed on the posture before;
* steady pair: ``i -> j`` measured in the ``--cycles``-th cycle of the pair ``i, j`` repeated;

then each table's Pearson and Spearman correlation with exact physics (scipy's, ties
averaged) and its mean absolute error, and the forward move per step of the reference gait in
its exact trial.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np
from scipy.stats import spearmanr

from qdsega.assembly import assemble
from qdsega.baselines.reference_search import reference_gait
from qdsega.description import Formation, load_formation, resolve_formation
from qdsega.locomotion.env import replay_postures, rules_env
from qdsega.locomotion.lower_agent import LowerAgent
from qdsega.locomotion.memo import SETTLE_S, MeasuredTransitions
from qdsega.simulation.bullet import BulletSimulation
from qdsega.task import Task, move_pose, relative_move
from qdsega.training.config import TrainingConfig, resolve_config

Move = tuple[float, float, float] | None


class Bench:
    """One simulation that measures moves after a chosen history."""

    def __init__(self, formation: Formation, config: TrainingConfig) -> None:
        self.formation = formation
        self.sim = BulletSimulation(robot=assemble(formation), settings=config.physics)
        self.agent = LowerAgent(sim=self.sim, config=config.lower_agent)
        self.pristine = self.sim.save_state()
        self.rest = np.array(formation.rest_levels())
        self.settle = round(SETTLE_S / config.physics.time_step_s)
        self.cache: dict[tuple, Move] = {}

    def _from_rest(self) -> None:
        self.sim.restore_state(self.pristine)
        self.sim.reset(self.formation.posture_rad(self.rest))
        self.sim.step(self.settle)

    def _move(self, target: np.ndarray) -> Move:
        start = self.agent.pose().planar
        outcome = self.agent.execute(np.asarray(target))
        return None if outcome.failed else relative_move(start, outcome.pose.planar)

    def after(self, h: tuple, i: tuple, j: tuple) -> Move:
        """``i -> j`` right after ``h -> i``, ``h`` reached from rest and settled."""
        key = ("after", h, i, j)
        if key not in self.cache:
            self._from_rest()
            reached = not self.agent.execute(np.array(h)).failed
            self.sim.step(self.settle)
            reached = reached and not self.agent.execute(np.array(i)).failed
            self.cache[key] = self._move(np.array(j)) if reached else None
        return self.cache[key]

    def steady(self, i: tuple, j: tuple, cycles: int) -> Move:
        """``i -> j`` in the ``cycles``-th cycle of ``i, j, i, j, ...`` from rest."""
        key = ("steady", i, j, cycles)
        if key not in self.cache:
            self._from_rest()
            move: Move = None if self.agent.execute(np.array(i)).failed else (0.0, 0.0, 0.0)
            for _ in range(cycles):
                if move is None:
                    break
                move = self._move(np.array(j))
                if move is not None and self._move(np.array(i)) is None:
                    move = None
            self.cache[key] = move
        return self.cache[key]


def chain(task: Task, moves: list[Move]) -> float:
    """Distance toward the light of a trial made of ``moves`` (nan if one failed)."""
    pose = (0.0, 0.0, 0.0)
    for move in moves:
        if move is None:
            return float("nan")
        pose = move_pose(*pose, *move)
    return task.covered((0.0, 0.0, 0.0), pose)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("formation", nargs="?", default="snake5", type=Path)
    parser.add_argument("--gaits", type=int, default=24)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--cycles", type=int, default=5)
    args = parser.parse_args()
    config = resolve_config(preset="paper-snake", overrides={"sim": "memo"})
    formation = load_formation(resolve_formation(args.formation))
    task = Task(config=config.task, light_xy=formation.light.position_m)
    steps = config.task.trial_steps
    env = rules_env(formation, config.rules())
    memo = MeasuredTransitions(
        formation=formation, lower_agent=config.lower_agent, physics=config.physics, workers=1
    )
    bench = Bench(formation, config)
    rng = np.random.default_rng(args.seed)
    counts = [len(j.levels_rad) for j in formation.joints]
    gaits = [
        [tuple(int(rng.integers(n)) for n in counts) for _ in range(2 + k % 3)]
        for k in range(args.gaits)
    ]
    reference = reference_gait(formation, rules=config.rules())
    period = reference.postures[: reference.params.period_steps]
    gaits.insert(0, [tuple(int(x) for x in p) for p in period])
    rest = tuple(int(x) for x in formation.rest_levels())
    print("period   exact  settled  after h  steady pair")
    rows = []
    for gait in gaits:
        sequence = [gait[k % len(gait)] for k in range(steps)]
        sources = [rest, *sequence[:-1]]
        exact = replay_postures(env, np.array(sequence))
        table = memo.transitions(np.array(sources), np.array(sequence))
        settled: list[Move] = [
            None if table.failed[t, t] else (table.dx[t, t], table.dy[t, t], table.dtheta[t, t])
            for t in range(steps)
        ]
        after = [settled[0]]
        after += [bench.after(sources[t - 1], sources[t], sequence[t]) for t in range(1, steps)]
        steady = [settled[0]]
        steady += [bench.steady(sources[t], sequence[t], args.cycles) for t in range(1, steps)]
        row = (
            exact.distance_m if exact.failure is None else float("nan"),
            chain(task, settled),
            chain(task, after),
            chain(task, steady),
        )
        rows.append(row)
        print(f"{len(gait):6d} " + " ".join(f"{v:8.3f}" for v in row))
    data = np.array(rows)
    ok = ~np.isnan(data).any(axis=1)
    for k, name in enumerate(("settled", "after h", "steady pair"), start=1):
        pearson = np.corrcoef(data[ok, 0], data[ok, k])[0, 1]
        spearman = spearmanr(data[ok, 0], data[ok, k]).statistic  # ties averaged
        error = np.mean(np.abs(data[ok, 0] - data[ok, k]))
        print(
            f"{name}: Pearson {pearson:.2f}, Spearman {spearman:.2f}, "
            f"mean |error| {error:.3f} m ({ok.sum()} gaits)"
        )
    env.reset(seed=0)
    moves = []
    for posture in reference.postures:
        before = env.pose()
        env.step(posture)
        moves.append(relative_move(before, env.pose())[0])
    print("reference gait, forward move per step (mm):", " ".join(f"{1e3 * m:.0f}" for m in moves))


if __name__ == "__main__":
    main()
