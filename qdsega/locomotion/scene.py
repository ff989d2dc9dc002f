"""Where a PyBullet episode starts: a formation settled in its start posture in a world, the
trial's frame at its pose, the light, and the camera that follows the body. Both PyBullet envs
(:mod:`qdsega.locomotion.env`, :mod:`qdsega.locomotion.joint_env`) start every episode here.

Poses are in the trial's frame, as the task has them: the body's pose after settling
(:mod:`qdsega.locomotion.body_pose`) is the origin, heading +x, and the light stands at the
formation's distance and bearing from it.
"""

from __future__ import annotations

import math
import warnings
from pathlib import Path

import numpy as np

from qdsega.assembly import assemble
from qdsega.description import Formation, World, load_formation, named_world, resolve_formation
from qdsega.errors import QdsegaWarning, WorldError
from qdsega.locomotion.body_pose import BodyPose
from qdsega.locomotion.lower_agent import SETTLE_S, LowerAgent, LowerAgentConfig
from qdsega.simulation import PhysicsSettings
from qdsega.simulation.bullet import BulletSimulation
from qdsega.simulation.camera import LIGHT_RADIUS_FRACTION, CameraConfig, body_extent_m
from qdsega.task import Pose, move_pose, relative_move


def lit(
    formation: Formation | Path | str, world: World | Path | str | None
) -> tuple[Formation, World]:
    """The formation (itself, a formation file or a shipped one's name) with the world's
    light where it has one, and the world (itself, a world file, a shipped one's name, or
    None for the flat plane)."""
    if not isinstance(formation, Formation):
        formation = load_formation(resolve_formation(formation))
    if world is None:
        world = World()
    elif not isinstance(world, World):
        world = named_world(world)
    return world.lights(formation), world


class Scene:
    """One formation settled in its start posture in one world.

    Args:
        formation: the robot, lit as it walks (:func:`lit`).
        world: the ground and what stands on it.
        lower_agent: how postures are executed and when the body has failed.
        physics: engine settings.
        start_rad: the start posture (rad), shape (J,).
        pictures: render camera pictures (:meth:`picture`) off-screen, with pybullet's EGL
            plugin or its TinyRenderer (with a :class:`~qdsega.errors.QdsegaWarning`).
        window: open PyBullet's window (:meth:`aim_window`); where there is no display, a
            :class:`~qdsega.errors.QdsegaWarning` says so and none opens.

    Raises:
        WorldError: the body starts inside an obstacle.
    """

    def __init__(
        self,
        *,
        formation: Formation,
        world: World,
        lower_agent: LowerAgentConfig,
        physics: PhysicsSettings,
        start_rad: np.ndarray,
        pictures: bool = False,
        window: bool = False,
    ) -> None:
        self.start_rad = start_rad
        self.sim = BulletSimulation(
            robot=assemble(formation), settings=physics, egl=pictures, world=world, window=window
        )
        if pictures and not self.sim.egl_enabled:
            warnings.warn("EGL unavailable, rendered with TinyRenderer", QdsegaWarning, 3)
        self.lower_agent = LowerAgent(sim=self.sim, config=lower_agent)
        try:
            self.sim.reset(start_rad)
        except WorldError:  # it starts inside an obstacle: nothing to keep open
            self.sim.close()
            raise
        self.sim.step(max(1, round(SETTLE_S / self.sim.settings.time_step_s)))
        self._origin = self.lower_agent.pose().planar
        light = formation.light
        self.light_xy = move_pose(*self._origin, *light.position_m, 0.0)[:2]
        """Where the light stands in the world (m)."""
        if pictures or window:
            self.sim.add_light(
                self.light_xy, radius_m=max(0.1, LIGHT_RADIUS_FRACTION * light.distance_m)
            )
            self._body_extent_m = body_extent_m(self.sim.unit_states()[0])  # at rest: framing
        self._start_state = self.sim.save_state()

    def restart(self) -> None:
        """Back to the settled start, the joints commanded to the start posture."""
        self.sim.restore_state(self._start_state)
        self.sim.command(self.start_rad)

    def trial_pose(self, pose: BodyPose) -> Pose:
        """A pose of the body in the trial's frame."""
        return relative_move(self._origin, pose.planar)

    def picture(self, camera: CameraConfig) -> np.ndarray:
        """What ``camera`` sees now, (height, width, 3) uint8: the body from behind, looking
        toward the light (built with ``pictures``)."""
        target, yaw = self._view()
        return self.sim.camera_image(
            width=camera.width,
            height=camera.height,
            target_m=target,
            view_yaw_rad=yaw,
            distance_m=camera.distance_for(self._body_extent_m),
            pitch_rad=camera.pitch_rad,
            fov_deg=camera.fov_deg,
        )

    def aim_window(self, camera: CameraConfig) -> None:
        """Point the window's camera as ``camera`` would stand (built with ``window``)."""
        target, yaw = self._view()
        self.sim.aim_window(
            target_m=target,
            view_yaw_rad=yaw,
            distance_m=camera.distance_for(self._body_extent_m),
            pitch_rad=camera.pitch_rad,
        )

    def _view(self) -> tuple[tuple[float, float, float], float]:
        """Where a following camera looks (m): at the body, and along which yaw (rad): toward
        the light."""
        pose = self.lower_agent.pose()
        light_x, light_y = self.light_xy
        yaw = math.atan2(light_y - pose.y_m, light_x - pose.x_m)
        return (pose.x_m, pose.y_m, 0.05), yaw

    def close(self) -> None:
        self.sim.close()
