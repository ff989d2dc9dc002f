import io

import numpy as np
import pytest

from qdsega.description import load_formation, resolve_formation, resolve_world
from qdsega.description.world import load_world
from qdsega.errors import QdsegaWarning
from qdsega.locomotion.lower_agent import LowerAgentConfig
from qdsega.locomotion.memo import (
    PROGRESS_DELAY_S,
    SPOT_SPACING_M,
    MeasuredTransitions,
    spots_toward,
)
from qdsega.locomotion.surroundings import blocked_spots, too_tall, world_task
from qdsega.progress import ProgressLine
from qdsega.simulation.settings import PhysicsSettings
from qdsega.task import TaskConfig
from qdsega.training.sims import _blocked


@pytest.fixture(scope="module")
def snake5():
    return load_formation("assemblies/snake5.yaml")


def _postures(count: int) -> np.ndarray:
    return np.random.default_rng(0).integers(0, 9, size=(count, 4))


@pytest.mark.slow
def test_measurements_do_not_depend_on_order_or_workers(snake5):
    postures = _postures(3)
    serial = MeasuredTransitions(formation=snake5, lower_agent=LowerAgentConfig(), workers=1)
    forward = serial.transitions(postures, postures[::-1])
    reverse = MeasuredTransitions(formation=snake5, lower_agent=LowerAgentConfig(), workers=1)
    backward = reverse.transitions(postures[::-1], postures)
    assert np.array_equal(forward.dx, backward.dx[::-1, ::-1])
    assert np.array_equal(forward.dtheta, backward.dtheta[::-1, ::-1])
    parallel = MeasuredTransitions(formation=snake5, lower_agent=LowerAgentConfig(), workers=2)
    try:
        assert np.array_equal(parallel.transitions(postures, postures[::-1]).dx, forward.dx)
    finally:
        parallel.close()


def test_each_transition_is_measured_once_and_survives_a_save(snake5, tmp_path):
    postures = _postures(3)
    memo = MeasuredTransitions(formation=snake5, lower_agent=LowerAgentConfig(), workers=1)
    first = memo.transitions(postures, postures)
    assert memo.measured == 9
    memo.transitions(postures[:2], postures)
    assert memo.measured == 9
    memo.save(tmp_path / "memo.npz")
    again = MeasuredTransitions(formation=snake5, lower_agent=LowerAgentConfig(), workers=1)
    again.load(tmp_path / "memo.npz")
    assert len(again) == 9
    second = again.transitions(postures, postures)
    assert again.measured == 0
    for field in ("dx", "dy", "dtheta", "failed"):
        assert np.array_equal(getattr(first, field), getattr(second, field))


def test_staying_put_goes_nowhere_and_a_wave_step_moves(snake5):
    memo = MeasuredTransitions(formation=snake5, lower_agent=LowerAgentConfig(), workers=1)
    still = np.array([[4, 4, 4, 4]])
    assert abs(memo.transitions(still, still).dx[0, 0]) < 1e-3
    bent = memo.transitions(np.array([[0, 4, 8, 4]]), np.array([[4, 8, 4, 0]]))
    assert not bent.failed[0, 0]
    assert np.hypot(bent.dx[0, 0], bent.dy[0, 0]) > 1e-3


def test_failures_are_recorded_for_a_legged_body():
    quadruped = load_formation("assemblies/quadruped.yaml")
    memo = MeasuredTransitions(formation=quadruped, lower_agent=LowerAgentConfig(), workers=1)
    start = np.array([quadruped.rest_levels()])
    all_up = start.copy()
    for leg in quadruped.legs:
        all_up[0, quadruped.joint_index(leg.lift_joint)] = 1
    table = memo.transitions(start, np.vstack([start, all_up]))
    assert list(table.failed[0]) == [False, True]


def test_a_table_in_the_same_process_measures_with_its_own_physics(snake5):
    """One process, one formation object, two physics settings: each table measures with its
    own (the worker's simulation is rebuilt, not reused for the wrong settings)."""
    postures = _postures(2)
    coarse = PhysicsSettings(time_step_s=1 / 120, solver_iterations=10)
    tables = []
    for physics in (PhysicsSettings(), coarse, PhysicsSettings()):
        memo = MeasuredTransitions(
            formation=snake5, lower_agent=LowerAgentConfig(), physics=physics, workers=1
        )
        tables.append(memo.transitions(postures, postures).dx)
    assert not np.array_equal(tables[0], tables[1])
    assert np.array_equal(tables[0], tables[2])


def test_a_batch_shows_its_progress_only_through_the_factory_given(snake5, capsys):
    postures = _postures(3)
    quiet = MeasuredTransitions(formation=snake5, lower_agent=LowerAgentConfig(), workers=1)
    quiet.transitions(postures, postures)
    assert capsys.readouterr().err == ""  # no factory: silent
    stream, made = io.StringIO(), []

    def factory(label: str, total: int, *, delay_s: float = 0.0, initial: int = 0) -> ProgressLine:
        made.append((label, total, delay_s))
        return ProgressLine(label, total, stream=stream)  # no delay: every batch shows

    shown = MeasuredTransitions(
        formation=snake5, lower_agent=LowerAgentConfig(), workers=1, progress=factory
    )
    shown.transitions(postures, postures)
    shown.transitions(postures, postures)  # nothing left to measure: no line
    assert made == [("measuring transitions", 9, PROGRESS_DELAY_S)]
    last = stream.getvalue().splitlines()[-1]
    assert last.startswith("measuring transitions 9/9: memo table 9 transitions, elapsed ")


def test_a_move_is_the_mean_over_spots_and_fails_where_any_fails():
    quadruped = load_formation("assemblies/quadruped.yaml")
    rest = np.array([quadruped.rest_levels()])
    step = rest.copy()
    step[0, quadruped.joint_index(quadruped.legs[0].swing_joint)] += 1
    tunnel = load_world("worlds/tunnel.yaml")  # a roof from 0.4 m: no legged body fits
    one, inside = ((0.0, 0.0),), ((0.0, 0.0), (0.0, 0.0), (1.0, 0.0))

    def measure(spots, world=None):
        memo = MeasuredTransitions(
            formation=quadruped, lower_agent=LowerAgentConfig(), workers=1, world=world,
            spots=spots,
        )  # fmt: skip
        return memo.transitions(rest, step)

    alone = measure(one, tunnel)
    assert not alone.failed[0, 0]
    twice = measure(((0.0, 0.0), (0.0, 0.0)), tunnel)
    assert twice.dx[0, 0] == alone.dx[0, 0] and not twice.failed[0, 0]  # same spot, same mean
    assert measure(inside, tunnel).failed[0, 0]  # placed inside the roof at one of three
    flat = measure(((0.0, 0.0), (1.0, 0.0)))  # the plane is the same everywhere: about the same
    assert flat.dx[0, 0] == pytest.approx(measure(one).dx[0, 0], abs=1e-3)


def test_spots_lie_toward_the_light():
    assert spots_toward((10.0, 0.0), 3) == (
        (0.0, 0.0),
        (SPOT_SPACING_M, 0.0),
        (2 * SPOT_SPACING_M, 0.0),
    )
    (_, (x, y)) = spots_toward((0.0, -5.0), 2)
    assert x == pytest.approx(0.0, abs=1e-12) and y == pytest.approx(-SPOT_SPACING_M)
    with pytest.raises(ValueError, match="at least 1"):
        spots_toward((1.0, 0.0), 0)


def test_the_starts_a_body_cannot_stand_at_are_found_and_said_in_one_line():
    tunnel = load_world(resolve_world("tunnel"))
    quadruped = tunnel.lights(load_formation(resolve_formation("quadruped")))
    spots = spots_toward(tuple(quadruped.light.position_m), 6)
    blocked = blocked_spots(quadruped, physics=PhysicsSettings(), world=tunnel, spots=spots)
    assert blocked == list(spots[2:])  # the roof begins between 0.25 and 0.5 m: too low for it
    line = _blocked(quadruped, tunnel, spots, blocked)
    assert "cannot stand clear of obstacles at 4 of the 6 places" in line
    assert "from the other 2" in line
    assert "\n" not in line
    assert blocked_spots(quadruped, physics=PhysicsSettings(), world=tunnel, spots=spots[:1]) == []


def test_a_roof_too_low_for_the_body_is_in_its_way_and_one_it_fits_under_is_not(snake5):
    tunnel = load_world(resolve_world("tunnel"))  # a roof 9 cm high from 0.4 m ahead
    quadruped = tunnel.lights(load_formation(resolve_formation("quadruped")))
    physics = PhysicsSettings()
    assert too_tall(quadruped, tunnel, physics) and not too_tall(snake5, tunnel, physics)
    task = world_task(quadruped, TaskConfig(), tunnel, physics)
    assert task.obstacles is not None
    assert not task.obstacles.touches(0.0, 0.0, 0.0) and task.obstacles.touches(1.0, 0.0, 0.0)
    assert task.exterior((0.2, 0.0, 0.0)) >= len(task.edges)  # the roof's edge is sensed ahead
    assert world_task(snake5, TaskConfig(), tunnel, physics).obstacles is None


def test_training_measures_moves_only_where_the_body_can_stand(tmp_path):
    from qdsega.training.config import TrainingConfig
    from qdsega.training.sims import build_sim

    tunnel = load_world(resolve_world("tunnel"))
    quadruped = tunnel.lights(load_formation(resolve_formation("quadruped")))
    # under the roof it cannot stand, and at 0.25 m its front is within half a unit of the roof
    with pytest.warns(QdsegaWarning, match="cannot stand clear of obstacles at 5 of the 6 places"):
        sim = build_sim(quadruped, TrainingConfig(sim="memo", workers=1), tmp_path, world=tunnel)
    try:
        assert sim.grounded is not None
        assert sim.grounded.base.spots == spots_toward(tuple(quadruped.light.position_m), 1)
    finally:
        sim.close()


def test_training_measures_moves_clear_of_obstacles_and_refuses_where_none_is(tmp_path):
    """A post on the way: the starts where the body touches it are left out. A long block
    just ahead of the start, which the body touches (given a wide clearance) at every start:
    said in one line."""
    from qdsega.description.world import Box, World
    from qdsega.errors import WorldError
    from qdsega.locomotion.surroundings import body_outline_m
    from qdsega.obstacle_map import ObstacleMap
    from qdsega.task import Task
    from qdsega.training.config import TrainingConfig
    from qdsega.training.sims import build_sim, memo_starts

    quadruped = load_formation(resolve_formation("quadruped"))
    config = TrainingConfig(sim="memo", workers=1)
    post = World(name="post", boxes=(Box((0.8, 0.0, 0.15), (0.1, 0.1, 0.3), 0.0),))
    with pytest.warns(QdsegaWarning, match="clear of obstacles at 2 of the 6 places"):
        sim = build_sim(quadruped, config, tmp_path, world=post)
    try:
        assert sim.task.obstacles is not None and sim.task.n_exterior == 12
        assert sim.grounded is not None
        assert [x for x, _ in sim.grounded.base.spots] == [0.0, 0.25, 0.5, 1.25]
    finally:
        sim.close()
    block = World(name="block", boxes=(Box((1.26, 0.0, 0.1), (2.1, 1.0, 0.2), 0.0),))
    outline = body_outline_m(quadruped, config.physics)
    wide = ObstacleMap.of(block, outline_m=outline, clearance_m=0.12)
    task = Task(config=config.task, light_xy=quadruped.light.position_m, obstacles=wide)
    with pytest.raises(WorldError, match=r"touches an obstacle of block at every place[^\n]*$"):
        memo_starts(quadruped, config, block, task)
