"""The assembled files alone: does the URDF play the toolkit's trial, and how far does the
same trial go in MuJoCo from the MJCF?

Usage: .venv/bin/python experiments/file_physics/run.py [--bodies quadruped,snake5]
           [--seconds 6] [--hold 0.5] [--mujoco-timestep S] [--full-torque-error-deg D]

Each body plays fixed joint commands on flat ground from its rest posture, after a 0.5 s
settle: a legged body each classic gait (alternating, wave, pairs), one posture every
``--hold`` seconds (the lower agent's step); a snake a travelling wave, 20 deg, 1 Hz, 90 deg
between neighbouring joints, commanded every physics step. Four ways:

* ``toolkit``: ``BulletSimulation``, the toolkit's own load;
* ``file+flags``: the same world and engine, the body replaced by ``loadURDF`` of the
  assembled file with the flags qdsega loads it with (inertia from the file, self-collision
  but for parent-child pairs), the friction that the file does not carry left out;
* ``file``: the same, a plain ``loadURDF(file)`` without flags;
* ``mujoco``: the MJCF of ``qdsega assemble --mjcf`` in MuJoCo as written (its floor, time
  step and actuators), from its ``rest`` keyframe; ``--mujoco-timestep`` and
  ``--full-torque-error-deg`` change its time step and its actuators' gain after loading, to
  see how much the distances depend on them.

It prints the distance the root unit covered along +x (toward the light) and across (y) in
each, and the largest difference of any unit's position from the toolkit's trial.
"""

from __future__ import annotations

import argparse
import math
import sys
import tempfile
from collections.abc import Callable
from pathlib import Path

import mujoco
import numpy as np
import pybullet

from qdsega.assembly import assemble, write_assembly
from qdsega.assembly.mjcf import assemble_mjcf
from qdsega.baselines.classic_gaits import leg_gait
from qdsega.description import Formation, load_formation, resolve_formation
from qdsega.locomotion.lower_agent import SETTLE_S
from qdsega.simulation.bullet import BulletSimulation

FLAGS = (
    pybullet.URDF_USE_INERTIA_FROM_FILE
    | pybullet.URDF_USE_SELF_COLLISION
    | pybullet.URDF_USE_SELF_COLLISION_EXCLUDE_PARENT
)
Commands = Callable[[float], np.ndarray]
"""Joint targets (rad), shape (J,), at a time (s) after the settle."""


def commands_of(formation: Formation, gait: str, *, seconds: float, hold_s: float) -> Commands:
    """The trial's joint targets: a classic gait's postures, or the snake's wave."""
    if gait == "wave-1hz":
        lags = np.arange(len(formation.joints)) * math.pi / 2
        return lambda t: math.radians(20.0) * np.sin(2 * math.pi * t - lags)
    postures = leg_gait(formation, gait=gait, steps=math.ceil(seconds / hold_s))
    angles = np.array([formation.posture_rad(p) for p in postures])
    return lambda t: angles[min(int(t / hold_s), len(angles) - 1)]


def bullet_trial(
    formation: Formation, commands: Commands, seconds: float, *, file: Path | None, flags: int
) -> np.ndarray:
    """Every unit's position (m), shape (U, 3), relative to the root's after the settle; with
    ``file``, on a body loaded from it in place of the toolkit's."""
    with BulletSimulation(robot=assemble(formation)) as sim:
        if file is not None:
            sim.client.removeBody(sim.body_id)
            sim.body_id = sim.client.loadURDF(str(file), flags=flags)
        sim.reset(np.array(formation.posture_rad(formation.rest_levels())))
        dt = sim.settings.time_step_s
        sim.step(round(SETTLE_S / dt))
        start = sim.unit_states()[0][0]
        for k in range(round(seconds / dt)):
            sim.command(commands(k * dt))
            sim.step()
        return sim.unit_states()[0] - start


def mujoco_trial(
    formation: Formation,
    commands: Commands,
    seconds: float,
    *,
    timestep_s: float | None,
    full_torque_error_deg: float | None,
) -> np.ndarray:
    """The root unit's position (m), shape (1, 3), relative to its own after the settle."""
    model = mujoco.MjModel.from_xml_string(assemble_mjcf(assemble(formation)))
    if timestep_s is not None:
        model.opt.timestep = timestep_s
    if full_torque_error_deg is not None:
        for i, joint in enumerate(formation.joints):  # actuators are in formation order
            kp = joint.spec.effort_nm / math.radians(full_torque_error_deg)
            model.actuator_gainprm[i, 0], model.actuator_biasprm[i, 1] = kp, -kp
    data = mujoco.MjData(model)
    mujoco.mj_resetDataKeyframe(model, data, 0)
    root = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, formation.root.name)
    steps = round(SETTLE_S / model.opt.timestep)
    mujoco.mj_step(model, data, steps)
    start = data.xipos[root].copy()  # the centre of mass, as PyBullet's base position
    for k in range(round(seconds / model.opt.timestep)):
        data.ctrl[:] = commands(k * model.opt.timestep)
        mujoco.mj_step(model, data)
    return (data.xipos[root] - start)[None, :]


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--bodies", default="quadruped,snake5", help="formations, commas")
    parser.add_argument("--seconds", type=float, default=6.0, help="trial length after settle")
    parser.add_argument("--hold", type=float, default=0.5, help="seconds a gait posture")
    parser.add_argument("--mujoco-timestep", type=float, help="MuJoCo's time step (s)")
    parser.add_argument(
        "--full-torque-error-deg", type=float, help="MuJoCo actuators' kp = effort / this"
    )
    args = parser.parse_args()
    print(f"{'body':10} {'gait':12} {'way':11} {'x_m':>8} {'y_m':>8} {'max_diff_m':>11}")
    with tempfile.TemporaryDirectory() as folder:
        for name in args.bodies.split(","):
            formation = load_formation(resolve_formation(Path(name)))
            file = Path(folder) / f"{formation.name}.urdf"
            write_assembly(assemble(formation), file)
            gaits = ("alternating", "wave", "pairs") if formation.legs else ("wave-1hz",)
            for gait in gaits:
                commands = commands_of(formation, gait, seconds=args.seconds, hold_s=args.hold)
                toolkit = bullet_trial(formation, commands, args.seconds, file=None, flags=0)
                ways = {
                    "toolkit": toolkit,
                    "file+flags": bullet_trial(
                        formation, commands, args.seconds, file=file, flags=FLAGS
                    ),
                    "file": bullet_trial(formation, commands, args.seconds, file=file, flags=0),
                    "mujoco": mujoco_trial(
                        formation,
                        commands,
                        args.seconds,
                        timestep_s=args.mujoco_timestep,
                        full_torque_error_deg=args.full_torque_error_deg,
                    ),
                }
                for way, positions in ways.items():
                    diff = (
                        f"{np.abs(positions - toolkit).max():11.2e}"
                        if positions.shape == toolkit.shape
                        else f"{'':11}"
                    )
                    x, y = positions[0, :2]
                    print(f"{formation.name:10} {gait:12} {way:11} {x:8.3f} {y:8.3f} {diff}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
