"""A run folder's greedy policy, or any posture sequence, as a video."""

from __future__ import annotations

import math
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

import numpy as np

from qdsega.adaptation.folders import AdaptationFolder
from qdsega.analysis.evaluation import replay_policy, replayable_run
from qdsega.analysis.recorder import Film, picture, record
from qdsega.analysis.video import VIDEO_SUFFIXES, write_video
from qdsega.description import Formation, World
from qdsega.errors import ConfigError, FormationError
from qdsega.locomotion.env import LocomotionEnv, replay_postures, rules_env
from qdsega.simulation.camera import CameraConfig, body_extent_m


def render_run(run: Path, out: Path, camera: CameraConfig) -> Film:
    """Film the run's greedy policy in exact physics (the postures ``qdsega evaluate`` replays,
    replayed anew if the run has no evaluation yet) and write the video to ``out``."""
    _check_suffix(out)
    film = _run_film(run, camera)
    write_video(film.frames, out, fps=film.fps)
    return film


def render_postures(
    formation: Formation,
    postures: np.ndarray,
    out: Path,
    camera: CameraConfig,
    *,
    world: World | None = None,
) -> Film:
    """Film ``postures`` (steps, J) of level indices in ``world`` (default flat) and write the
    video to ``out``."""
    _check_suffix(out)
    postures = np.asarray(postures, dtype=np.int64).reshape(-1, len(formation.joints))
    counts = np.array([len(j.levels_rad) for j in formation.joints])
    if np.any(postures < 0) or np.any(postures >= counts):
        raise FormationError(f"postures hold levels outside 0..(levels - 1) of {formation.name}")
    env = LocomotionEnv(formation=formation, render_mode="rgb_array", camera=camera, world=world)
    try:
        return _film(env, postures, out)
    finally:
        env.close()


def render_adaptation(folder: Path, changed: Formation, world: World, camera: CameraConfig) -> Film:
    """Film the gait an adaptation of ``changed`` found, in ``world``, into its folder."""
    files = AdaptationFolder(folder)
    postures = read_postures(files.gait, len(changed.joints))
    return render_postures(world.lights(changed), postures, files.video, camera, world=world)


def final_still(run: Path, camera: CameraConfig) -> np.ndarray:
    """The picture at the end of the run's evaluated trial, (height, width, 3) uint8: where its
    gait took the body. The trial is played unfilmed and pictured once."""
    with _run_env(run, camera) as (env, postures):
        replay_postures(env, postures)
        return picture(env)


def rest_still(
    formation: Formation,
    camera: CameraConfig,
    *,
    world: World | None = None,
    turn_deg: float = 0.0,
) -> np.ndarray:
    """The body at rest where a trial starts, (height, width, 3) uint8, seen from behind its
    root unit (not along its heading, as a trial is filmed): pictures of the bodies a root
    unit keeps show them in one frame. ``turn_deg`` turns the camera around the body
    (counter-clockwise seen from above) for a view from the side."""
    env = LocomotionEnv(formation=formation, render_mode="rgb_array", camera=camera, world=world)
    try:
        env.reset()
        centres, _ = env.sim.unit_states()
        _, (x, y, z, w) = env.sim.base_pose()
        root_yaw = math.atan2(2.0 * (w * z + x * y), 1.0 - 2.0 * (y * y + z * z))
        return env.sim.camera_image(
            width=camera.width,
            height=camera.height,
            target_m=(*centres[:, :2].mean(axis=0), 0.05),
            view_yaw_rad=root_yaw + math.radians(turn_deg),
            distance_m=camera.distance_for(body_extent_m(centres)),
            pitch_rad=camera.pitch_rad,
            fov_deg=camera.fov_deg,
        )
    finally:
        env.close()


def _run_film(run: Path, camera: CameraConfig) -> Film:
    """The run's greedy policy filmed in its own world."""
    with _run_env(run, camera) as (env, postures):
        return record(env, postures)


@contextmanager
def _run_env(run: Path, camera: CameraConfig) -> Iterator[tuple[LocomotionEnv, np.ndarray]]:
    """A rendering env of the run's body under its rules in its own world, and the postures
    of its greedy trial: those ``qdsega evaluate`` replayed, or replayed anew where the run
    has no evaluation yet."""
    finished = replayable_run(run)
    formation = finished.formation
    evaluation = finished.folder.read_evaluation()
    env = rules_env(formation, finished.config.rules(finished.world), camera=camera)
    try:
        if evaluation is not None:
            postures = np.array(evaluation["postures"])
        else:
            postures = np.array(replay_policy(env, finished.policy)["postures"])
        yield env, postures
    finally:
        env.close()


def _film(env: LocomotionEnv, postures: np.ndarray, out: Path) -> Film:
    film = record(env, postures)
    write_video(film.frames, out, fps=film.fps)
    return film


def read_postures(file: Path, joints: int) -> np.ndarray:
    """A posture sequence from a CSV file: one row per step, one level index per joint."""
    try:
        rows = np.loadtxt(file, delimiter=",", dtype=np.int64, ndmin=2, comments="#")
    except (OSError, ValueError) as exc:
        raise FormationError(f"cannot read postures: {exc}", file=file) from None
    if rows.shape[1] != joints or len(rows) == 0:
        raise FormationError(f"expected rows of {joints} level indices", file=file)
    return rows


def _check_suffix(out: Path) -> None:
    if out.suffix.lower() not in VIDEO_SUFFIXES:
        raise ConfigError(f"video must end in {' or '.join(VIDEO_SUFFIXES)}", file=out)
