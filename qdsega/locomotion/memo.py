"""Memo mode: PyBullet posture-to-posture transitions, each measured once and kept.

The paper's lower agent makes every upper-agent step a move from one posture to another. A
transition ``i -> j`` is measured once: the robot is settled on the ground in posture ``i``
(teleported into it, then left to rest for ``SETTLE_S``), commanded to ``j`` through the lower
agent, and the move of its body (:mod:`qdsega.locomotion.body_pose`) is expressed in the body
frame at the start: forward ``dx`` (m), leftward ``dy`` (m), turn ``dtheta`` (rad), and whether
the lower agent failed. Starting from a settled posture, not from wherever the robot happened to
be, is the approximation that makes the table possible; ``qdsega evaluate`` measures its cost
by replaying policies with exact physics.

Where the ground varies (stairs, rough ground, a roof), a move depends on where it is made, so
each is measured from several starts ``spots`` along the way to the light: the table keeps the
mean move over them, and the move fails where it failed at any of them, for a trial crosses all
that ground. So the table holds what the body can expect over the ground ahead, not the move at
the origin alone.

Missing transitions are filled on demand, grouped by start posture (one settle, a snapshot,
then every target from that snapshot) and spread over worker processes. Each worker builds the
world once; every measurement restores a snapshot, so results do not depend on which worker
made them or in which order.
"""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path

import numpy as np

from qdsega.agent.model import Transitions
from qdsega.assembly import assemble
from qdsega.atomic import replaced_atomically
from qdsega.description import Formation, World
from qdsega.errors import WorldError
from qdsega.locomotion.lower_agent import SETTLE_S, LowerAgent, LowerAgentConfig
from qdsega.locomotion.surroundings import blocked_spots
from qdsega.progress import ProgressFactory
from qdsega.simulation import PhysicsSettings
from qdsega.simulation.bullet import BulletSimulation
from qdsega.task import Task, relative_move
from qdsega.workers.pool import Pool, worker_pool

PROGRESS_DELAY_S = 5.0
"""A batch of measurements shows progress only once it has taken this long (s): the many short
batches of a training run stay quiet between its per-generation lines."""

_FIELDS = 4  # dx, dy, dtheta, failed

SPOT_SPACING_M = 0.25
"""How far apart the spots a move is measured from lie along the way to the light (m)."""


def spots_toward(light_xy: tuple[float, float], count: int) -> tuple[tuple[float, float], ...]:
    """``count`` spots from the origin toward the light, ``SPOT_SPACING_M`` apart."""
    if count < 1:
        raise ValueError(f"count must be at least 1, got {count}")
    heading = np.arctan2(light_xy[1], light_xy[0])
    return tuple(
        (k * SPOT_SPACING_M * float(np.cos(heading)), k * SPOT_SPACING_M * float(np.sin(heading)))
        for k in range(count)
    )


class MeasuredTransitions:
    """A :class:`qdsega.agent.model.TransitionProvider` backed by PyBullet measurements.

    Args:
        formation: the robot.
        lower_agent: how postures are executed and when that fails.
        physics: engine settings.
        start_levels: the posture every trial starts from (J,); default the rest posture.
        workers: processes measuring in parallel (1 measures in this process, unless
            ``ray`` is given).
        ray: measure on Ray actors instead of processes: ``local`` or a cluster address
            (:mod:`qdsega.workers.ray_cluster`); the table is the same bit for bit.
        progress: makes the line that shows a batch's transitions measured of all, for
            batches that take longer than ``PROGRESS_DELAY_S`` (None: silent).
        world: the ground the moves are measured on (default flat).
        spots: where each move is measured from a settled start heading +x, as (x, y) (m);
            default the origin alone.
    """

    def __init__(
        self,
        *,
        formation: Formation,
        lower_agent: LowerAgentConfig,
        physics: PhysicsSettings | None = None,
        start_levels: tuple[int, ...] | None = None,
        workers: int = 2,
        ray: str | None = None,
        progress: ProgressFactory | None = None,
        world: World | None = None,
        spots: tuple[tuple[float, float], ...] = ((0.0, 0.0),),
    ) -> None:
        if workers < 1:
            raise ValueError(f"workers must be at least 1, got {workers}")
        lower_agent.step_duration_for(formation)  # refuses a step too short for a joint
        self.formation = formation
        self.lower_agent = lower_agent
        self.physics = physics or PhysicsSettings()
        self.workers = workers
        self.ray = ray
        self.progress = progress
        self.world = world or World()
        if not spots:
            raise ValueError("spots must hold at least one place")
        self.spots = spots
        self._start = np.array(start_levels or formation.rest_levels(), dtype=np.int64)
        self._table: dict[bytes, np.ndarray] = {}
        self._pool: Pool | None = None
        self._stored: tuple[Path, int] | None = None  # file holding the whole table, its size
        self.measured = 0
        """Transitions measured by this object (not loaded from a file)."""

    @property
    def n_joints(self) -> int:
        return len(self.formation.joints)

    def start_posture(self) -> np.ndarray:
        return self._start.copy()

    def __len__(self) -> int:
        return len(self._table)

    def transitions(self, from_postures: np.ndarray, to_postures: np.ndarray) -> Transitions:
        """Outcomes (n, m) of commanding each of ``to_postures`` (m, J) from each of (n, J)."""
        sources = np.asarray(from_postures, dtype=np.int64)
        targets = np.asarray(to_postures, dtype=np.int64)
        self._fill(sources, targets)
        values = np.array(
            [[self._table[_key(i, j)] for j in targets] for i in sources], dtype=np.float64
        ).reshape(len(sources), len(targets), _FIELDS)
        return Transitions(
            dx=values[..., 0],
            dy=values[..., 1],
            dtheta=values[..., 2],
            failed=values[..., 3] > 0.5,
        )

    def save(self, file: Path) -> None:
        """Write every known transition to ``file`` (npz), atomically; nothing to do when
        ``file`` already holds them all (the table only grows)."""
        if self._stored == (file, len(self._table)):
            return
        keys = sorted(self._table)
        pairs = np.array([np.frombuffer(k, dtype=np.int64) for k in keys]).reshape(
            len(keys), 2 * self.n_joints
        )
        values = np.array([self._table[k] for k in keys]).reshape(len(keys), _FIELDS)
        with replaced_atomically(file) as partial:
            np.savez_compressed(partial, pairs=pairs, values=values)
        self._stored = (file, len(self._table))

    def load(self, file: Path) -> None:
        """Add the transitions stored in ``file`` (written by :meth:`save`)."""
        with np.load(file) as data:
            pairs, values = data["pairs"], data["values"]
        if pairs.shape[1:] != (2 * self.n_joints,) or values.shape[1:] != (_FIELDS,):
            raise ValueError(f"{file} does not hold transitions of {self.formation.name}")
        for pair, value in zip(pairs, values, strict=True):
            self._table[pair.astype(np.int64).tobytes()] = value
        if len(self._table) == len(pairs):  # the table is exactly the file's
            self._stored = (file, len(self._table))

    def close(self) -> None:
        if self._pool is not None:
            self._pool.shutdown(cancel_futures=True)
            self._pool = None

    def _fill(self, sources: np.ndarray, targets: np.ndarray) -> None:
        jobs: list[tuple[np.ndarray, np.ndarray]] = []
        for source in np.unique(sources, axis=0):
            pending = [t for t in np.unique(targets, axis=0) if _key(source, t) not in self._table]
            if pending:
                jobs.append((source, np.array(pending)))
        if not jobs:
            return
        args = (self.formation, self.lower_agent, self.physics, self.world, self.spots)
        results: Iterator[np.ndarray]
        if self.workers == 1 and self.ray is None:
            _init_worker(*args)
            results = (_measure_from(*job) for job in jobs)
        else:
            if self._pool is None:
                self._pool = worker_pool(self.workers, _init_worker, args, ray=self.ray)
            results = iter(self._pool.map(_measure_from, *zip(*jobs, strict=True)))
        total = sum(len(missing) for _, missing in jobs)
        line = (
            None
            if self.progress is None
            else self.progress("measuring transitions", total, delay_s=PROGRESS_DELAY_S)
        )
        done = 0
        try:
            for (source, missing), rows in zip(jobs, results, strict=True):
                for target, row in zip(missing, rows, strict=True):
                    self._table[_key(source, target)] = row
                    self.measured += 1
                done += len(missing)
                if line is not None:
                    line.update(done, f"memo table {len(self._table):,} transitions")
        finally:
            if line is not None:
                line.close()


def _key(source: np.ndarray, target: np.ndarray) -> bytes:
    return np.concatenate([source, target]).astype(np.int64).tobytes()


def clear_spots(
    formation: Formation,
    *,
    task: Task,
    physics: PhysicsSettings,
    world: World,
    count: int,
) -> tuple[tuple[tuple[float, float], ...], list[tuple[float, float]]]:
    """The ``count`` spots toward ``task``'s light each move would be measured from, and those
    of them to leave out: where the body cannot stand, or touches an obstacle of ``task``'s
    map (:mod:`qdsega.obstacle_map`).

    Raises:
        WorldError: every spot is left out (one line).
    """
    spots = spots_toward((float(task.light[0]), float(task.light[1])), count)
    # one spot is the origin: training refuses a start inside an obstacle before it gets here
    inside = (
        [] if count == 1 else blocked_spots(formation, physics=physics, world=world, spots=spots)
    )
    obstacles = task.obstacles
    blocked = [
        s for s in spots if s in inside or (obstacles is not None and obstacles.touches(*s, 0.0))
    ]
    if len(blocked) == len(spots):
        end = spots[-1]
        raise WorldError(
            f"{formation.name} touches an obstacle of {world.name} at every place memo mode "
            f"measures its moves from (from the start to ({end[0]:.2f}, {end[1]:.2f}) m): clear "
            "the way ahead of the start, or learn with --sim pybullet"
        )
    return spots, blocked


class _Bench:
    """A worker's own simulation, lower agent and a snapshot right after loading."""

    def __init__(
        self,
        formation: Formation,
        lower_agent: LowerAgentConfig,
        physics: PhysicsSettings,
        world: World,
        spots: tuple[tuple[float, float], ...],
    ) -> None:
        self.formation = formation
        self.lower_agent = lower_agent
        self.physics = physics
        self.world = world
        self.spots = spots
        self.sim = BulletSimulation(robot=assemble(formation), settings=physics, world=world)
        self.agent = LowerAgent(sim=self.sim, config=lower_agent)
        self.pristine = self.sim.save_state()
        self.rest = np.array(formation.rest_levels(), dtype=np.int64)
        self.settle_steps = max(1, round(SETTLE_S / physics.time_step_s))


_bench: _Bench | None = None


def _init_worker(
    formation: Formation,
    lower_agent: LowerAgentConfig,
    physics: PhysicsSettings,
    world: World,
    spots: tuple[tuple[float, float], ...],
) -> None:
    global _bench
    if (
        _bench is None
        or _bench.formation is not formation
        or _bench.lower_agent != lower_agent
        or _bench.physics != physics
        or _bench.world != world
        or _bench.spots != spots
    ):
        if _bench is not None:
            _bench.sim.close()
        _bench = _Bench(formation, lower_agent, physics, world, spots)


def _measure_from(source: np.ndarray, targets: np.ndarray) -> np.ndarray:
    """Rows (dx m, dy m, dtheta rad, failed 0/1) for ``source -> target``, shape (m, 4): the
    mean move over the spots; failed where it failed at any spot, so a move that failed at one
    spot is not measured at the next."""
    bench = _bench
    assert bench is not None, "worker not initialised"
    failed = np.zeros(len(targets), dtype=bool)
    moved = np.zeros((len(targets), 3))
    for spot in bench.spots:
        alive = np.flatnonzero(~failed)
        if alive.size == 0:
            break
        each = _measure_at(bench, spot, source, targets[alive])
        moved[alive] += each[:, :3]
        failed[alive[each[:, 3] > 0.5]] = True
    rows = np.zeros((len(targets), _FIELDS))
    rows[failed, 3] = 1.0
    rows[~failed, :3] = moved[~failed] / len(bench.spots)
    return rows


def _measure_at(
    bench: _Bench, spot: tuple[float, float], source: np.ndarray, targets: np.ndarray
) -> np.ndarray:
    """The rows of :func:`_measure_from` from a settled start at ``spot``; every move fails
    where the body cannot be placed there (inside an obstacle)."""
    sim, agent = bench.sim, bench.agent
    rows = np.zeros((len(targets), _FIELDS))
    sim.restore_state(bench.pristine)
    try:
        sim.reset(bench.formation.posture_rad(bench.rest), xy_m=spot)
    except WorldError:
        rows[:, 3] = 1.0
        return rows
    sim.step(bench.settle_steps)
    if agent.execute(source).failed:  # not reachable from rest: teleport into it instead
        sim.restore_state(bench.pristine)
        try:
            sim.reset(bench.formation.posture_rad(source), xy_m=spot)
        except WorldError:
            rows[:, 3] = 1.0
            return rows
    sim.step(bench.settle_steps)
    settled = sim.save_state()
    start = agent.pose().planar
    for k, target in enumerate(targets):
        sim.restore_state(settled)
        outcome = agent.execute(target)
        if outcome.failed:
            rows[k] = (0.0, 0.0, 0.0, 1.0)
            continue
        rows[k] = (*relative_move(start, outcome.pose.planar), 0.0)
    sim.remove_state(settled)
    return rows
