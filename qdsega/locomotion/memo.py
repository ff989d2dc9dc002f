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

On a slope a move depends on which way the body faces: a snake facing uphill slides back along
its body, one lying across the slope barely slides. There each move is measured facing each of
``headings`` sectors of the compass and kept per sector (:class:`~qdsega.agent.world.Transitions`
rows), so a walk through the table slides as the body would where it faces; a body-frame slide
measured facing uphill would otherwise carry a body turned downhill up the hill. A body that
turns while it settles on the slope is placed again, turned back by as much, so that it starts
facing its sector.

Missing transitions are filled on demand, grouped by start posture (one settle, a snapshot,
then every target from that snapshot) and spread over worker processes. Each worker builds the
world once; every measurement restores a snapshot, so results do not depend on which worker
made them or in which order.
"""

from __future__ import annotations

import math
from collections.abc import Iterator
from pathlib import Path

import numpy as np

from qdsega.agent.world import Transitions
from qdsega.assembly import assemble
from qdsega.atomic import replaced_atomically
from qdsega.description import Formation, World
from qdsega.errors import WorldError
from qdsega.locomotion.lower_agent import SETTLE_S, LowerAgent, LowerAgentConfig
from qdsega.progress import ProgressFactory
from qdsega.simulation import PhysicsSettings
from qdsega.simulation.bullet import BulletSimulation
from qdsega.task import relative_move
from qdsega.workers.pool import Pool, worker_pool

PROGRESS_DELAY_S = 5.0
"""A batch of measurements shows progress only once it has taken this long (s): the many short
batches of a training run stay quiet between its per-generation lines."""

_FIELDS = 4  # dx, dy, dtheta, failed

HEADING_TRIES = 4
"""Where headings are told apart, how often a start is placed again, turned back by what the
body turned while it settled, until it faces its sector (the last try stands)."""

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
    """A :class:`qdsega.agent.world.TransitionProvider` backed by PyBullet measurements.

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
        spots: where each move is measured from a settled start, as (x, y) (m); default the
            origin alone.
        headings: sectors of the compass each move is measured facing (the centre of each;
            the first +x) and kept apart (1: facing +x alone).
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
        headings: int = 1,
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
        if headings < 1:
            raise ValueError(f"headings must be at least 1, got {headings}")
        self.headings = headings
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
        """Outcomes (headings * n, m) of commanding each of ``to_postures`` (m, J) from each of
        (n, J), a block of rows per heading."""
        sources = np.asarray(from_postures, dtype=np.int64)
        targets = np.asarray(to_postures, dtype=np.int64)
        self._fill(sources, targets)
        n, m = len(sources), len(targets)
        values = np.array(
            [[self._table[_key(i, j)] for j in targets] for i in sources], dtype=np.float64
        ).reshape(n, m, self.headings, _FIELDS)
        values = values.transpose(2, 0, 1, 3).reshape(self.headings * n, m, _FIELDS)
        return Transitions(
            dx=values[..., 0],
            dy=values[..., 1],
            dtheta=values[..., 2],
            failed=values[..., 3] > 0.5,
            headings=self.headings,
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
        values = np.array([self._table[k] for k in keys]).reshape(len(keys), self._width)
        with replaced_atomically(file) as partial:
            np.savez_compressed(partial, pairs=pairs, values=values)
        self._stored = (file, len(self._table))

    def load(self, file: Path) -> None:
        """Add the transitions stored in ``file`` (written by :meth:`save`)."""
        with np.load(file) as data:
            pairs, values = data["pairs"], data["values"]
        if pairs.shape[1:] != (2 * self.n_joints,) or values.shape[1:] != (self._width,):
            raise ValueError(
                f"{file} does not hold transitions of {self.formation.name} in "
                f"{self.headings} heading(s)"
            )
        for pair, value in zip(pairs, values, strict=True):
            self._table[pair.astype(np.int64).tobytes()] = value
        if len(self._table) == len(pairs):  # the table is exactly the file's
            self._stored = (file, len(self._table))

    @property
    def _width(self) -> int:
        """Numbers kept per transition: dx, dy, dtheta, failed in each heading."""
        return self.headings * _FIELDS

    def close(self) -> None:
        if self._pool is not None:
            self._pool.shutdown(cancel_futures=True)
            self._pool = None

    def _fill(self, sources: np.ndarray, targets: np.ndarray) -> None:
        jobs: list[tuple[np.ndarray, np.ndarray]] = []
        for source in np.unique(sources, axis=0):
            missing = [t for t in np.unique(targets, axis=0) if _key(source, t) not in self._table]
            if missing:
                jobs.append((source, np.array(missing)))
        if not jobs:
            return
        args = (
            self.formation,
            self.lower_agent,
            self.physics,
            self.world,
            self.spots,
            self.headings,
        )
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


class _Bench:
    """A worker's own simulation, lower agent and a snapshot right after loading."""

    def __init__(
        self,
        formation: Formation,
        lower_agent: LowerAgentConfig,
        physics: PhysicsSettings,
        world: World,
        spots: tuple[tuple[float, float], ...],
        headings: int,
    ) -> None:
        self.formation = formation
        self.lower_agent = lower_agent
        self.physics = physics
        self.world = world
        self.spots = spots
        self.headings = headings
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
    headings: int,
) -> None:
    global _bench
    if (
        _bench is None
        or _bench.formation is not formation
        or _bench.lower_agent != lower_agent
        or _bench.physics != physics
        or _bench.world != world
        or _bench.spots != spots
        or _bench.headings != headings
    ):
        if _bench is not None:
            _bench.sim.close()
        _bench = _Bench(formation, lower_agent, physics, world, spots, headings)


def _measure_from(source: np.ndarray, targets: np.ndarray) -> np.ndarray:
    """Rows for ``source -> target``, shape (m, headings * 4): in each heading, (dx m, dy m,
    dtheta rad, failed 0/1), the mean move over the spots; failed where it failed at any spot,
    so a move that failed at one spot is not measured at the next."""
    bench = _bench
    assert bench is not None, "worker not initialised"
    rows = np.zeros((len(targets), bench.headings, _FIELDS))
    for k in range(bench.headings):
        yaw = 2.0 * np.pi * k / bench.headings
        failed = np.zeros(len(targets), dtype=bool)
        moved = np.zeros((len(targets), 3))
        for spot in bench.spots:
            alive = np.flatnonzero(~failed)
            if alive.size == 0:
                break
            each = _measure_at(bench, spot, yaw, source, targets[alive])
            moved[alive] += each[:, :3]
            failed[alive[each[:, 3] > 0.5]] = True
        rows[failed, k, 3] = 1.0
        rows[~failed, k, :3] = moved[~failed] / len(bench.spots)
    return rows.reshape(len(targets), bench.headings * _FIELDS)


def _measure_at(
    bench: _Bench, spot: tuple[float, float], yaw: float, source: np.ndarray, targets: np.ndarray
) -> np.ndarray:
    """The rows of :func:`_measure_from` from a settled start at ``spot`` facing ``yaw``
    (rad); every move fails where the body cannot be placed there (inside an obstacle)."""
    sim, agent = bench.sim, bench.agent
    rows = np.zeros((len(targets), _FIELDS))
    placed = yaw
    for _ in range(HEADING_TRIES if bench.headings > 1 else 1):
        if not _settle_in(bench, spot, placed, source):
            rows[:, 3] = 1.0
            return rows
        missed = math.remainder(agent.pose().planar[2] - yaw, 2.0 * math.pi)
        if abs(missed) <= math.pi / bench.headings:
            break
        placed -= missed  # the body turned while it settled (on a slope): place it turned back
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


def _settle_in(bench: _Bench, spot: tuple[float, float], yaw: float, source: np.ndarray) -> bool:
    """Settle the body at ``spot`` facing ``yaw`` (rad), then in posture ``source``, settled
    again; False where it cannot be placed there (inside an obstacle)."""
    sim, agent = bench.sim, bench.agent
    sim.restore_state(bench.pristine)
    try:
        sim.reset(bench.formation.posture_rad(bench.rest), xy_m=spot, yaw_rad=yaw)
    except WorldError:
        return False
    sim.step(bench.settle_steps)
    if agent.execute(source).failed:  # not reachable from rest: teleport into it instead
        sim.restore_state(bench.pristine)
        try:
            sim.reset(bench.formation.posture_rad(source), xy_m=spot, yaw_rad=yaw)
        except WorldError:
            return False
    sim.step(bench.settle_steps)
    return True
