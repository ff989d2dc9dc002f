"""PyBullet simulation of an assembled formation.

This is the only module that imports pybullet. Each :class:`BulletSimulation` owns its own
``BulletClient`` (never the global client), in DIRECT mode so that simulations can coexist, or
in GUI mode for a window to watch it in (PyBullet opens one per process).
"""

from __future__ import annotations

import importlib.util
import math
import os
import sys
import tempfile
import warnings
import weakref
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from qdsega.assembly import AssembledRobot, write_assembly
from qdsega.description.world import World
from qdsega.errors import QdsegaWarning, WorldError
from qdsega.simulation.quiet import native_output_silenced
from qdsega.simulation.settings import PhysicsSettings
from qdsega.simulation.terrain import build_terrain, ground_height

with native_output_silenced(2):  # pybullet prints its build time to stderr on import
    import pybullet
    import pybullet_data
    from pybullet_utils.bullet_client import BulletClient

PLANE_URDF = Path(pybullet_data.getDataPath()) / "plane.urdf"
"""The flat ground."""
_DROP_CLEARANCE_M = 0.002
"""Gap between the robot's lowest point and the ground when it is placed (m)."""

_EGL_OPEN: weakref.WeakSet[BulletSimulation] = weakref.WeakSet()
"""Simulations of this process that render with EGL and are not closed."""
_EGL_PARKED: list[BulletClient] = []
"""Clients of closed EGL simulations, disconnected when the last open one closes."""


class BulletSimulation:
    """One robot on a flat ground plane, joints under position control.

    Args:
        robot: the assembled formation.
        settings: engine parameters.
        egl: load pybullet's EGL plugin for off-screen OpenGL camera images (it must be loaded
            before any body); see :attr:`egl_enabled` for whether it loaded. Either way the
            world is then built for pictures (rough ground shows its relief).
        world: the ground and what stands on it (:mod:`qdsega.simulation.terrain`); None for
            the flat plane.
        window: open PyBullet's window (a GUI client) to watch the simulation in, the world
            built for pictures; where there is no display (Linux without ``DISPLAY``) it
            says so in a :class:`~qdsega.errors.QdsegaWarning` and runs without one (see
            :attr:`window`).
    """

    def __init__(
        self,
        *,
        robot: AssembledRobot,
        settings: PhysicsSettings | None = None,
        egl: bool = False,
        world: World | None = None,
        window: bool = False,
    ) -> None:
        self.robot = robot
        self.formation = robot.formation
        self.settings = settings or PhysicsSettings()
        # PyBullet's GUI client ends the whole process where it cannot reach X.
        self.window = window and (sys.platform != "linux" or bool(os.environ.get("DISPLAY")))
        """Whether PyBullet's window is open."""
        if window and not self.window:
            warnings.warn(
                "no PyBullet window without a display (DISPLAY is not set): running without one",
                QdsegaWarning,
                stacklevel=2,
            )
        mode = pybullet.GUI if self.window else pybullet.DIRECT
        with native_output_silenced(1):  # the engine prints its banner to the C-level stdout
            self.client = BulletClient(connection_mode=mode)
        self.egl_enabled = egl and self._load_egl()
        if self.egl_enabled:
            _EGL_OPEN.add(self)
        self._configure_engine()
        self.world = world or World()
        self.terrain = build_terrain(
            self.client, pybullet, self.world, PLANE_URDF, pictures=egl or window
        )
        flags = pybullet.URDF_USE_INERTIA_FROM_FILE
        if self.settings.self_collision:
            flags |= pybullet.URDF_USE_SELF_COLLISION | (
                pybullet.URDF_USE_SELF_COLLISION_EXCLUDE_PARENT
            )
        # The engine reads the file (and its meshes) as it loads: the folder goes at once, so
        # that a process killed later leaves nothing behind.
        with tempfile.TemporaryDirectory(prefix="qdsega-urdf-") as folder:
            urdf_file = Path(folder) / f"{self.formation.name}.urdf"
            write_assembly(robot, urdf_file)
            with native_output_silenced(1):
                self.body_id = self.client.loadURDF(str(urdf_file), flags=flags)
        self.link_index = self._link_indices()
        self._unit_link_indices = [self.link_index[u.name] for u in self.formation.units]
        self._unit_of_link = {index: name for name, index in self.link_index.items()}
        # Called every few physics steps: bound once, as BulletClient builds a new partial
        # function on every attribute lookup.
        self._step_simulation = self.client.stepSimulation
        self._get_link_states = self.client.getLinkStates
        self._get_base_pose = self.client.getBasePositionAndOrientation
        self._get_contact_points = self.client.getContactPoints
        joint_index = self._joint_indices()
        self.joint_names = tuple(j.name for j in self.formation.joints)
        self.joint_ids = np.array([joint_index[name] for name in self.joint_names], dtype=int)
        self._efforts = [j.spec.effort_nm for j in self.formation.joints]
        self._speeds = [j.spec.velocity_rad_s for j in self.formation.joints]
        self._apply_friction()

    # -- set-up ------------------------------------------------------------------------------

    def _configure_engine(self) -> None:
        c, s = self.client, self.settings
        c.setGravity(0.0, 0.0, -s.gravity_m_s2)
        c.setPhysicsEngineParameter(
            fixedTimeStep=s.time_step_s,
            numSolverIterations=s.solver_iterations,
            deterministicOverlappingPairs=int(s.deterministic_pairs),
        )

    def _link_indices(self) -> dict[str, int]:
        root_name = self.client.getBodyInfo(self.body_id)[0].decode()
        indices = {root_name: -1}
        for j in range(self.client.getNumJoints(self.body_id)):
            indices[self.client.getJointInfo(self.body_id, j)[12].decode()] = j
        return indices

    def _joint_indices(self) -> dict[str, int]:
        return {
            self.client.getJointInfo(self.body_id, j)[1].decode(): j
            for j in range(self.client.getNumJoints(self.body_id))
        }

    def _apply_friction(self) -> None:
        """The ground's friction, and each unit's anisotropic friction: the URDF carries the
        units' lateral friction, but PyBullet's URDF reader has no element for anisotropy."""
        ground = self.settings.ground_friction * self.world.friction
        for body in self.terrain.ground:
            self.client.changeDynamics(body, -1, lateralFriction=ground)
        for unit in self.formation.units:
            if not unit.friction.is_isotropic:
                self.client.changeDynamics(
                    self.body_id,
                    self.link_index[unit.name],
                    anisotropicFriction=list(unit.friction.anisotropic),
                )

    # -- state ---------------------------------------------------------------------------------

    def reset(
        self,
        joint_positions_rad: Sequence[float] | np.ndarray,
        *,
        xy_m: tuple[float, float] = (0.0, 0.0),
        yaw_rad: float = 0.0,
    ) -> None:
        """Place the robot just above the ground at rest with the given joint angles.

        Args:
            joint_positions_rad: one angle per actuated joint (rad), shape (J,).
            xy_m: root unit's centre of mass on the ground (m).
            yaw_rad: root heading (rad).
        """
        positions = np.asarray(joint_positions_rad, dtype=float)
        if positions.shape != self.joint_ids.shape:
            raise ValueError(f"expected {len(self.joint_ids)} joint angles, got {positions.shape}")
        c = self.client
        orientation = c.getQuaternionFromEuler((0.0, 0.0, yaw_rad))
        c.resetBasePositionAndOrientation(self.body_id, (xy_m[0], xy_m[1], 1.0), orientation)
        c.resetBaseVelocity(self.body_id, (0.0, 0.0, 0.0), (0.0, 0.0, 0.0))
        for joint_id, angle in zip(self.joint_ids, positions, strict=True):
            c.resetJointState(self.body_id, int(joint_id), float(angle), 0.0)
        boxes = [c.getAABB(self.body_id, index) for index in self.link_index.values()]
        lift = max(self._ground_under(low, high) - low[2] for low, high in boxes)
        c.resetBasePositionAndOrientation(
            self.body_id, (xy_m[0], xy_m[1], 1.0 + lift + _DROP_CLEARANCE_M), orientation
        )
        self.command(positions)
        self._refuse_a_start_inside_an_obstacle()

    def _ground_under(self, low: Sequence[float], high: Sequence[float]) -> float:
        """The highest ground under a link's bounding box (its corners and centre) (m)."""
        if self.world.is_flat:
            return 0.0
        xs = np.array([low[0], high[0], low[0], high[0], (low[0] + high[0]) / 2])
        ys = np.array([low[1], low[1], high[1], high[1], (low[1] + high[1]) / 2])
        return float(ground_height(self.world, xs, ys).max())

    def _refuse_a_start_inside_an_obstacle(self) -> None:
        if not self.terrain.obstacles:
            return
        self.client.performCollisionDetection()
        for body in self.terrain.obstacles:
            points = self._get_contact_points(bodyA=self.body_id, bodyB=body)
            hits = [p for p in points if p[8] < -_DROP_CLEARANCE_M]
            if hits:
                unit = self._unit_of_link[hits[0][3]]
                raise WorldError(
                    f"{self.formation.name} starts inside an obstacle of {self.world.name} "
                    f"(unit {unit}); move the obstacle or make the way wider",
                    file=self.world.file,
                )

    def command(
        self, joint_targets_rad: Sequence[float] | np.ndarray, *, speed_rad_s: float | None = None
    ) -> None:
        """Drive every actuated joint toward its target (rad), shape (J,), with at most its
        torque limit and at most its speed limit (or ``speed_rad_s`` where that is lower).

        Far from the target the motor runs at that speed, so joints move at constant speed."""
        targets = np.asarray(joint_targets_rad, dtype=float)
        if targets.shape != self.joint_ids.shape:
            raise ValueError(f"expected {len(self.joint_ids)} joint targets, got {targets.shape}")
        speeds = self._speeds if speed_rad_s is None else np.minimum(self._speeds, speed_rad_s)
        for joint_id, target, effort, speed in zip(
            self.joint_ids, targets, self._efforts, speeds, strict=True
        ):
            self.client.setJointMotorControl2(
                self.body_id,
                int(joint_id),
                pybullet.POSITION_CONTROL,
                targetPosition=float(target),
                force=effort,
                maxVelocity=float(speed),
                positionGain=self.settings.position_gain,
            )

    def step(self, steps: int = 1) -> None:
        """Advance the physics by ``steps`` time steps."""
        for _ in range(steps):
            self._step_simulation()

    def joint_positions(self) -> np.ndarray:
        """Actuated joint angles (rad), shape (J,)."""
        return self.joint_states()[0]

    def joint_states(self) -> tuple[np.ndarray, np.ndarray]:
        """Actuated joint angles (rad) and angular velocities (rad/s), shape (J,) each."""
        if len(self.joint_ids) == 0:
            return np.zeros(0), np.zeros(0)
        states = self.client.getJointStates(self.body_id, self.joint_ids.tolist())
        return np.array([s[0] for s in states], dtype=float), np.array(
            [s[1] for s in states], dtype=float
        )

    def base_pose(self) -> tuple[np.ndarray, np.ndarray]:
        """Root unit's centre of mass (m), shape (3,), and orientation quaternion (x, y, z, w)."""
        position, orientation = self.client.getBasePositionAndOrientation(self.body_id)
        return np.array(position), np.array(orientation)

    def base_velocity(self) -> tuple[np.ndarray, np.ndarray]:
        """Root unit's linear velocity (m/s) and angular velocity (rad/s) in the world frame,
        shape (3,) each."""
        linear, angular = self.client.getBaseVelocity(self.body_id)
        return np.array(linear), np.array(angular)

    def unit_states(self, rows: Sequence[int] | None = None) -> tuple[np.ndarray, np.ndarray]:
        """Centre of mass (m), shape (U, 3), and orientation quaternion (x, y, z, w), shape
        (U, 4), in the world frame, of every unit in formation order (or of the units at
        ``rows`` of that order, in the order given)."""
        links = (
            self._unit_link_indices if rows is None else [self._unit_link_indices[r] for r in rows]
        )
        children = [i for i in links if i >= 0]
        states = self._get_link_states(self.body_id, children) if children else []
        by_index = {i: (state[0], state[1]) for i, state in zip(children, states, strict=True)}
        if -1 in links:
            # PyBullet's base frame is the root unit's inertial frame: its position is the COM.
            by_index[-1] = self._get_base_pose(self.body_id)
        found = [by_index[i] for i in links]
        return (
            np.array([f[0] for f in found], dtype=float).reshape(-1, 3),
            np.array([f[1] for f in found], dtype=float).reshape(-1, 4),
        )

    def save_state(self) -> int:
        """Snapshot the whole physics state in memory; returns its id for restore_state."""
        return self.client.saveState()

    def restore_state(self, state_id: int) -> None:
        """Return to a snapshot taken with save_state (positions, velocities, contacts)."""
        self.client.restoreState(stateId=state_id)

    def remove_state(self, state_id: int) -> None:
        """Free a snapshot taken with save_state."""
        self.client.removeState(state_id)

    def place_joints(
        self, joint_ids: Sequence[int] | np.ndarray, angles_rad: Sequence[float] | np.ndarray
    ) -> None:
        """Set the joints with PyBullet ids ``joint_ids`` (see :attr:`joint_ids`) to these
        angles (rad) at once, without physics: to look at a posture, not to move into it."""
        if len(joint_ids):
            self.client.resetJointStatesMultiDof(
                self.body_id, [int(j) for j in joint_ids], [[float(a)] for a in angles_rad]
            )

    def self_contacts(self) -> list[tuple[str, str, float]]:
        """Pairs of this robot's units that touch or overlap now, as (unit, unit, signed
        distance (m), negative where they overlap). Parent-child pairs never count, nor any
        pair when self-collision is off (:class:`PhysicsSettings`)."""
        self.client.performCollisionDetection()
        points = self._get_contact_points(bodyA=self.body_id, bodyB=self.body_id)
        return [(self._unit_of_link[p[3]], self._unit_of_link[p[4]], p[8]) for p in points]

    def ground_contacts(self) -> set[str]:
        """Names of the units that touch the ground (the plane, rough ground, steps) now."""
        units = set()
        for ground in self.terrain.ground:
            points = self._get_contact_points(bodyA=self.body_id, bodyB=ground)
            units |= {self._unit_of_link[p[3]] for p in points}
        return units

    # -- pictures ------------------------------------------------------------------------------

    def _load_egl(self) -> bool:
        """Load the EGL renderer plugin; False (TinyRenderer then) when it does not load."""
        spec = importlib.util.find_spec("eglRenderer")
        if spec is None or spec.origin is None:
            return False
        with native_output_silenced(1), native_output_silenced(2):
            return self.client.loadPlugin(spec.origin, "_eglRendererPlugin") >= 0

    def add_light(self, xy_m: tuple[float, float], *, radius_m: float) -> None:
        """Show the light source as a glowing sphere resting on the ground at ``xy_m`` (m)."""
        base = float(ground_height(self.world, np.array([xy_m[0]]), np.array([xy_m[1]]))[0])
        shape = self.client.createVisualShape(
            pybullet.GEOM_SPHERE, radius=radius_m, rgbaColor=(1.0, 0.85, 0.1, 1.0)
        )
        self.client.createMultiBody(
            baseMass=0.0,
            baseVisualShapeIndex=shape,
            basePosition=(xy_m[0], xy_m[1], base + radius_m),
        )

    def tint(self, units: Sequence[str], rgba: Sequence[float]) -> None:
        """Colour the named units (red, green, blue, alpha in 0..1), for a picture that points
        them out; the physics is untouched."""
        for unit in units:
            self.client.changeVisualShape(self.body_id, self.link_index[unit], rgbaColor=rgba)

    def camera_image(
        self,
        *,
        width: int,
        height: int,
        target_m: Sequence[float],
        view_yaw_rad: float,
        distance_m: float,
        pitch_rad: float,
        fov_deg: float,
    ) -> np.ndarray:
        """RGB image (height, width, 3), uint8, of a camera ``distance_m`` behind ``target_m``
        looking along ``view_yaw_rad`` (world, counter-clockwise from +x) and down by
        ``pitch_rad``."""
        direction = (
            math.cos(pitch_rad) * math.cos(view_yaw_rad),
            math.cos(pitch_rad) * math.sin(view_yaw_rad),
            -math.sin(pitch_rad),
        )
        eye = [t - distance_m * d for t, d in zip(target_m, direction, strict=True)]
        view = self.client.computeViewMatrix(eye, list(target_m), [0.0, 0.0, 1.0])
        projection = self.client.computeProjectionMatrixFOV(fov_deg, width / height, 0.02, 200.0)
        renderer = (
            pybullet.ER_BULLET_HARDWARE_OPENGL if self.egl_enabled else pybullet.ER_TINY_RENDERER
        )
        with native_output_silenced(1):  # the EGL plugin reports its GL vendor on stdout
            _, _, rgba, _, _ = self.client.getCameraImage(
                width, height, view, projection, renderer=renderer
            )
        return np.asarray(rgba, dtype=np.uint8).reshape(height, width, 4)[:, :, :3].copy()

    def aim_window(
        self, *, target_m: Sequence[float], view_yaw_rad: float, distance_m: float, pitch_rad: float
    ) -> None:
        """Point the window's camera as :meth:`camera_image` points its own (nothing without
        a window)."""
        # PyBullet's yaw 0 looks along +y, and its pitch is negative looking down.
        self.client.resetDebugVisualizerCamera(
            cameraDistance=distance_m,
            cameraYaw=math.degrees(view_yaw_rad) - 90.0,
            cameraPitch=-math.degrees(pitch_rad),
            cameraTargetPosition=list(target_m),
        )

    def close(self) -> None:
        """Disconnect from the physics server.

        pybullet's EGL plugin ends the process-wide EGL display when any client that loaded
        it disconnects, and every other client still rendering then crashes (a segmentation
        fault). So a simulation that renders with EGL is parked when it closes, and the parked
        ones disconnect together when the last open one closes."""
        if self.client is not None:
            if self.egl_enabled:
                _EGL_OPEN.discard(self)
                _EGL_PARKED.append(self.client)
                if not _EGL_OPEN:
                    for client in _EGL_PARKED:
                        _disconnect(client)
                    _EGL_PARKED.clear()
            else:
                _disconnect(self.client)
            self.client = None

    def __enter__(self) -> BulletSimulation:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


def _disconnect(client: BulletClient) -> None:
    with native_output_silenced(1):
        client.disconnect()
