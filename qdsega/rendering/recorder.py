"""Film a formation executing a posture sequence, off-screen.

The scene is set up as :class:`qdsega.locomotion.env.LocomotionEnv` sets up a trial (start
posture, settle, then one lower-agent step per posture), so the film shows the motion the
environment simulates. Frames come from pybullet's EGL renderer (OpenGL, also on a machine
without a GPU through Mesa) or, where that plugin does not load, from its TinyRenderer.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from qdsega.assembly import assemble
from qdsega.description import Formation
from qdsega.locomotion.env import SETTLE_S
from qdsega.locomotion.lower_agent import LowerAgent, LowerAgentConfig
from qdsega.rendering.camera import CameraConfig
from qdsega.simulation import PhysicsSettings
from qdsega.simulation.bullet import BulletSimulation

LIGHT_RADIUS_FRACTION = 0.02
"""The light's sphere has this fraction of its distance as radius (at least 0.1 m), so that it
shows on the horizon."""


@dataclass(frozen=True)
class Film:
    """Frames of a recording.

    Attributes:
        frames: RGB images, each (height, width, 3), uint8.
        fps: frames per second of simulated time.
        egl: whether the EGL renderer made them (else TinyRenderer).
        failure: why the lower agent stopped early, if it did.
    """

    frames: list[np.ndarray]
    fps: int
    egl: bool
    failure: str | None


def record(
    formation: Formation,
    postures: np.ndarray,
    *,
    lower_agent: LowerAgentConfig,
    camera: CameraConfig,
    physics: PhysicsSettings | None = None,
    start_levels: tuple[int, ...] | None = None,
) -> Film:
    """Execute ``postures`` (steps, J) from the start posture and film every 1/fps s."""
    with BulletSimulation(robot=assemble(formation), settings=physics, egl=True) as sim:
        agent = LowerAgent(sim=sim, config=lower_agent)
        start = start_levels or formation.rest_levels()
        sim.reset(formation.posture_rad(start))
        sim.step(max(1, round(SETTLE_S / sim.settings.time_step_s)))
        light = formation.light
        sim.add_light(light.position_m, radius_m=max(0.1, LIGHT_RADIUS_FRACTION * light.distance_m))
        frames: list[np.ndarray] = []
        every = max(1, round(1.0 / (camera.fps * sim.settings.time_step_s)))
        counter = 0

        def film() -> None:
            nonlocal counter
            if counter % every == 0:
                frames.append(_frame(sim, agent, formation, camera))
            counter += 1

        film()
        failure = None
        for posture in postures:
            outcome = agent.execute(np.asarray(posture), on_physics_step=film)
            if outcome.failed:
                failure = outcome.failure
                break
        return Film(frames=frames, fps=camera.fps, egl=sim.egl_enabled, failure=failure)


def _frame(
    sim: BulletSimulation, agent: LowerAgent, formation: Formation, camera: CameraConfig
) -> np.ndarray:
    pose = agent.pose()
    light_x, light_y = formation.light.position_m
    toward_light = math.atan2(light_y - pose.y_m, light_x - pose.x_m)
    return sim.camera_image(
        width=camera.width,
        height=camera.height,
        target_m=(pose.x_m, pose.y_m, 0.05),
        view_yaw_rad=toward_light,
        distance_m=camera.distance_m,
        pitch_rad=camera.pitch_rad,
        fov_deg=camera.fov_deg,
    )
