"""The obstacle map: footprints grown by the body, the sensed states, and the rules that use
it in the compiled loop and in Python alike."""

from __future__ import annotations

import math

import numpy as np
import pytest

from qdsega.agent.model import Transitions
from qdsega.agent.qlearning import learn_on_table
from qdsega.agent.space import ExplorationSpace
from qdsega.agent.table_model import TableModel
from qdsega.description import World
from qdsega.description.world import Box, Ceiling, Corridor, Stairs
from qdsega.obstacle_map import CELL_M, SENSED_STATES, ObstacleMap
from qdsega.task import Task, TaskConfig

POST = Box(xyz_m=(1.0, 0.0, 0.15), size_m=(0.1, 0.1, 0.3), yaw_rad=0.0)


CENTRE = np.zeros((1, 2))
"""A body that is a point: its clearance is its radius."""


def _map(*boxes: Box, radius_m: float = 0.2, outline_m: np.ndarray = CENTRE) -> ObstacleMap:
    found = ObstacleMap.of(
        World(name="boxes", boxes=boxes), outline_m=outline_m, clearance_m=radius_m
    )
    assert found is not None
    return found


def test_a_world_with_nothing_standing_has_no_map():
    assert ObstacleMap.of(World(), outline_m=CENTRE, clearance_m=0.2) is None
    stairs = Stairs(from_m=0.5, rise_m=0.05, run_m=0.3, count=3, width_m=4.0)
    assert (
        ObstacleMap.of(World(name="up", stairs=stairs), outline_m=CENTRE, clearance_m=0.2) is None
    )


def test_a_roof_is_on_the_map_only_for_a_body_too_tall_for_it():
    roof = Ceiling(height_m=0.09, from_m=0.4, to_m=2.0, width_m=1.0)
    tunnel = World(name="tunnel", ceiling=roof)
    assert ObstacleMap.of(tunnel, outline_m=CENTRE, clearance_m=0.1) is None
    tall = ObstacleMap.of(tunnel, outline_m=CENTRE, clearance_m=0.1, roof=True)
    assert tall is not None
    assert tall.touches(1.0, 0.0, 0.0) and tall.touches(0.35, 0.0, 0.0)
    assert not tall.touches(0.2, 0.0, 0.0) and not tall.touches(1.0, 0.65, 0.0)


def test_footprints_grow_by_the_clearance():
    obstacles = _map(POST, radius_m=0.2)
    edge = 0.05 + 0.2  # the post's half-size plus the growth
    assert obstacles.touches(1.0, 0.0, 0.0)
    assert obstacles.touches(1.0 - edge + 2 * CELL_M, 0.0, 0.0)
    assert not obstacles.touches(1.0 - edge - 2 * CELL_M, 0.0, 0.0)
    assert obstacles.touches(1.0, edge - 2 * CELL_M, 0.0)
    assert not obstacles.touches(1.0, edge + 2 * CELL_M, 0.0)
    corner = 0.05 + 0.2 / math.sqrt(2)  # the corners round off
    assert not obstacles.touches(1.0 + corner + 2 * CELL_M, corner + 2 * CELL_M, 0.0)
    assert not obstacles.touches(30.0, 0.0, 0.0)  # off the grid: open ground


def test_a_yawed_box_turns_its_footprint():
    long = Box(xyz_m=(0.0, 0.0, 0.1), size_m=(1.0, 0.1, 0.2), yaw_rad=math.radians(90))
    obstacles = _map(long, radius_m=0.05)
    assert obstacles.touches(0.0, 0.4, 0.0)
    assert not obstacles.touches(0.4, 0.0, 0.0)


def test_a_long_body_touches_a_wall_beside_it_only_when_turned_across():
    wall = Box(xyz_m=(0.0, 0.3, 0.15), size_m=(4.0, 0.1, 0.3), yaw_rad=0.0)
    snake = np.array([[-0.2, 0.0], [0.0, 0.0], [0.2, 0.0]])
    obstacles = _map(wall, radius_m=0.05, outline_m=snake)
    assert not obstacles.touches(0.0, 0.1, 0.0)
    assert obstacles.touches(0.0, 0.1, math.pi / 2)
    assert obstacles.nose_m == pytest.approx(0.25)


def test_corridor_walls_are_obstacles():
    world = World(name="corridor", corridor=Corridor(width_m=0.4, length_m=5.0, height_m=0.3))
    obstacles = ObstacleMap.of(world, outline_m=CENTRE, clearance_m=0.1)
    assert obstacles is not None
    assert not obstacles.touches(2.0, 0.0, 0.0)
    assert obstacles.touches(2.0, 0.15, 0.0) and obstacles.touches(2.0, -0.15, 0.0)


@pytest.mark.parametrize(
    ("pose", "sensed"),
    [
        ((0.0, 0.0, 0.0), 0),  # the post is beyond the rays' reach
        ((0.4, -0.1, 0.0), 1),  # ahead, to the left
        ((0.4, 0.1, 0.0), 2),  # ahead, to the right
        ((0.4, 0.0, math.pi), 0),  # behind
        ((0.4, 0.0, 0.0), 1),  # straight ahead: the left
    ],
)
def test_the_body_senses_the_nearer_side(pose, sensed):
    assert _map(POST).sensed(*pose) == sensed


def test_the_task_multiplies_the_light_bins_by_the_sensed_states():
    config = TaskConfig()
    plain = Task(config=config, light_xy=(50.0, 0.0))
    task = Task(config=config, light_xy=(50.0, 0.0), obstacles=_map(POST))
    assert task.n_exterior == plain.n_exterior * SENSED_STATES
    assert task.exterior((0.0, 0.0, 0.0)) == plain.exterior((0.0, 0.0, 0.0))
    ahead = (0.4, 0.1, 0.0)
    assert task.exterior(ahead) == plain.exterior(ahead) + 2 * plain.n_exterior


def test_a_move_into_an_obstacle_is_lost():
    task = Task(config=TaskConfig(), light_xy=(50.0, 0.0), obstacles=_map(POST))
    assert task.move((0.0, 0.0, 0.0), 0.5, 0.0, 0.0, False)[1:] == (pytest.approx(50.0), False)
    assert task.move((0.5, 0.0, 0.0), 0.4, 0.0, 0.3, False) == ((0.5, 0.0, 0.0), 0.0, False)


def test_the_compiled_loop_and_the_python_walk_meet_the_same_post():
    """Forced along the same commands (a greedy, alpha 1, gamma 0 walk; one command for each
    state), the compiled loop writes the rewards, sensed states and lost moves at the post
    that the Python walk gives."""
    task = Task(config=TaskConfig(trial_steps=20), light_xy=(50.0, 0.0), obstacles=_map(POST))
    postures = np.array([[0], [1], [2]])
    space = ExplorationSpace.from_population(postures, postures[0])
    n, m = space.n_interior, space.n_actions
    table = Transitions(
        dx=np.full((n, m), 0.1),
        dy=np.zeros((n, m)),
        dtheta=np.full((n, m), 0.01),
        failed=np.zeros((n, m), dtype=bool),
    )
    walk = TableModel(space=space, table=table, task=task)
    exterior, interior, visited, rewards = walk.start_trial(), 0, [], []
    for _ in range(task.trial_steps):
        a = (interior + 1) % m  # one command for each state
        result = walk.command(space.actions[a])
        visited.append((interior * task.n_exterior + exterior, a))
        rewards.append(result.reward)
        assert not result.failed
        interior, exterior = int(space.next_interior[a]), result.exterior
    assert rewards[-1] == 0.0 and walk.pose()[0] < 1.0  # stopped before the post
    assert any(s >= 4 for s, _ in visited)  # it sensed the post before it met it
    q = np.zeros((n * task.n_exterior, m))
    for s, a in visited:
        q[s, a] = 1e6
    distances, fell = np.zeros(1), np.zeros(1, dtype=np.bool_)
    steps = learn_on_table(
        q, *table.compiled(), space.next_interior, task.light, task.edges, *task.map_arrays(),
        1, task.trial_steps, 1.0, 0.0, np.array([1e-9, 0.0, 0.0]), task.config.reward_per_m,
        task.penalty, np.random.default_rng(0), np.zeros(m, dtype=np.int64), distances, fell,
    )  # fmt: skip
    assert steps == len(visited) == task.trial_steps and not fell[0]
    last = dict(zip(visited, rewards, strict=True))  # alpha 1: a pair keeps its last reward
    assert [q[pair] for pair in last] == pytest.approx(list(last.values()), rel=1e-12, abs=1e-12)
    assert distances[0] == pytest.approx(walk.distance_covered(), abs=1e-12)
