"""What PyBullet's own settings cost in fidelity and buy in speed, and whether several bodies
in one client step faster.

Usage: .venv/bin/python experiments/physics_fidelity/run.py [--bodies quadruped,legged12,snake5]
           [--worlds flat,slope,rubble] [--hz 240,120,60] [--iterations 50,20,10]
           [--settle 0.5,0.25,1] [--tolerance 0.05] [--steps 30] [--repeats 3]
           [--copies 1,2,4] [--copy-seconds 5] [--copy-repeats 5] [--json OUT.json]

Fidelity: on every body and world, fixed reference gaits (the classic leg gaits; for a snake
a fixed serpenoid and the serpenoid grid's best under the default physics; for both, the CPG
gait the package ships for flat ground) are replayed in exact physics (``LocomotionEnv``) at
every setting of physics rate (Hz), solver iterations and settle time; the first value of each
list is the reference (the toolkit's default 240 Hz, 50 iterations, 0.5 s). It prints each
setting's distances against the reference's and whether a gait's failure (or its step)
changed; then which gaits are steady (the reference physics keeps their outcome within
``--tolerance`` at every other settle time, i.e. when only the start moves a little) and which
settings keep every steady gait within ``--tolerance``. The settle time is a module constant,
``SETTLE_S``, that ``scene.py`` imports: this script sets ``qdsega.locomotion.scene.SETTLE_S``
while it builds an env (nothing in the package changes). The lower agent checks for failures
every ``check_interval_steps`` physics steps; the script scales it with the rate (12 at 240
Hz, 6 at 120 Hz, 3 at 60 Hz) so that every setting checks 20 times a second, as the default.

Speed: each rate and iteration count's trials are timed in ``--repeats`` rounds, the settings
interleaved within a round (its order turned by one every round), and the median round kept
(wall seconds per trial and per upper-agent step; failures shorten a trial, hence the second).
The settle time is spent once per env, before the snapshot every trial restores, so it costs
a trial nothing and is not timed.

Copies: ``--copies`` bodies of the same formation in one PyBullet client, 90 m apart on the
flat ground (a square grid: the plane is a 200 m square), each walking its default gait (wave
or serpenoid) under the default physics, timed as physics steps per second per body against
one body in its own client, in ``--copy-repeats`` interleaved rounds (the median); with the
copies in each other's collision filter (they could touch, but never do) and out of it. How
far each copy walked shows that every one moved as the single body did.
"""

from __future__ import annotations

import argparse
import itertools
import json
import math
import statistics
import sys
import tempfile
import time
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

import qdsega.locomotion.scene as scene_module
from qdsega.analysis.evaluation import classic_reference
from qdsega.assembly import assemble, write_assembly
from qdsega.baselines import classic_gaits
from qdsega.baselines.reference_search import SHIPPED_DIR, reference_gait, reference_key
from qdsega.description import Formation, World, load_formation, named_world, resolve_formation
from qdsega.locomotion.env import LocomotionEnv, Replay, replay_postures
from qdsega.locomotion.lower_agent import LowerAgentConfig
from qdsega.locomotion.rules import ExactRules
from qdsega.simulation import PhysicsSettings
from qdsega.simulation.bullet import BulletSimulation
from qdsega.task import TaskConfig

CHECK_RATE_HZ = 20.0
"""Failure checks per simulated second at every setting (the default's 12 steps at 240 Hz)."""
COPY_SPACING_M = 90.0
"""Distance between neighbouring copies in one client (m), on a square grid."""
GROUND_HALF_M = 95.0
"""How far from the origin a copy may stand (m): PyBullet's plane is a 200 m square, and a
body beyond its edge falls through nothing, which costs no contact at all."""


@dataclass(frozen=True, kw_only=True)
class Setting:
    """One cell of the grid: physics rate (Hz), solver iterations, settle time (s)."""

    hz: float
    iterations: int
    settle_s: float

    @property
    def label(self) -> str:
        return f"{self.hz:g} : {self.iterations} : {self.settle_s:g}"

    def physics(self) -> PhysicsSettings:
        return PhysicsSettings(time_step_s=1.0 / self.hz, solver_iterations=self.iterations)

    def lower_agent(self) -> LowerAgentConfig:
        return LowerAgentConfig(check_interval_steps=max(1, round(self.hz / CHECK_RATE_HZ)))


def number_list(text: str, kind: type, name: str) -> list[Any]:
    """``"240,120"`` -> [240.0, 120.0]; every value positive."""
    try:
        values = [kind(item) for item in text.split(",")]
    except ValueError:
        raise SystemExit(f"--{name}: {text!r} is not a comma-separated list of numbers") from None
    if not values or not all(v > 0 for v in values):
        raise SystemExit(f"--{name}: every value must be positive, got {text!r}")
    return values


@contextmanager
def settle_time(seconds: float) -> Iterator[None]:
    """``LocomotionEnv`` settles its start posture for ``seconds`` while inside."""
    kept = scene_module.SETTLE_S
    scene_module.SETTLE_S = seconds
    try:
        yield
    finally:
        scene_module.SETTLE_S = kept


def build_env(formation: Formation, world: World, setting: Setting, steps: int) -> LocomotionEnv:
    """The exact-physics env of ``formation`` in ``world`` at ``setting``."""
    with settle_time(setting.settle_s):
        return LocomotionEnv(
            formation=formation,
            task=TaskConfig(trial_steps=steps),
            lower_agent=setting.lower_agent(),
            physics=setting.physics(),
            world=world,
        )


def reference_gaits(
    formation: Formation, reference_env: LocomotionEnv, steps: int
) -> dict[str, np.ndarray]:
    """The gaits every setting replays: the classic leg gaits, or for a snake a fixed
    serpenoid and the serpenoid grid's best under the reference physics; and the CPG gait
    searched on flat ground under the default rules, where the package ships it."""
    if formation.legs:
        gaits = {
            gait: classic_gaits.leg_gait(formation, gait=gait, steps=steps)
            for gait in classic_gaits.LEG_GAITS
        }
    else:
        gaits = {"serpenoid 20/60/4": classic_gaits.default_gait(formation, steps=steps)}
        best = classic_reference(reference_env, formation)["params"]
        if best is not None:  # None: every candidate failed or went backward
            name = "grid best {amplitude_deg:.0f}/{phase_lag_deg:.0f}/{steps_per_cycle}"
            gaits[name.format(**best)] = classic_gaits.serpenoid(
                formation,
                amplitude_rad=math.radians(best["amplitude_deg"]),
                phase_lag_rad=math.radians(best["phase_lag_deg"]),
                steps_per_cycle=best["steps_per_cycle"],
                steps=steps,
            )
    key = reference_key(formation, rules=ExactRules())
    if (SHIPPED_DIR / f"{formation.name}-{key[:16]}.json").is_file():  # else it would search
        cpg = reference_gait(formation, rules=ExactRules(), workers=1)
        gaits["CPG (flat)"] = cpg.params.postures(formation, steps=steps)
    return gaits


def timed_replay(env: LocomotionEnv, postures: np.ndarray) -> tuple[Replay, float]:
    start = time.perf_counter()
    replay = replay_postures(env, postures)
    return replay, time.perf_counter() - start


def measure_body_world(
    formation: Formation, world: World, settings: list[Setting], steps: int, repeats: int
) -> dict[str, Any]:
    """Every setting's replays of the reference gaits, and the timed settings' wall times."""
    envs = {s: build_env(formation, world, s, steps) for s in settings}
    try:
        gaits = reference_gaits(formation, envs[settings[0]], steps)
        timed = [s for s in settings if s.settle_s == settings[0].settle_s]
        replays = {
            s: {g: replay_postures(envs[s], p) for g, p in gaits.items()}
            for s in settings
            if s not in timed
        }  # the timed settings' come from their first round
        rounds: dict[Setting, list[tuple[float, int]]] = {s: [] for s in timed}
        for round_index in range(repeats):
            turn = round_index % len(timed)
            for setting in timed[turn:] + timed[:turn]:
                wall, commands = 0.0, 0
                for name, postures in gaits.items():
                    replay, seconds = timed_replay(envs[setting], postures)
                    if replay != replays.setdefault(setting, {}).setdefault(name, replay):
                        raise SystemExit(f"{formation.name}: {name} replayed differently")
                    wall += seconds
                    commands += replay.completed + (replay.failure is not None)
                rounds[setting].append((wall / len(gaits), commands))
    finally:
        for env in envs.values():
            env.close()
    rows = []
    reference = replays[settings[0]]
    for setting in settings:
        timing = (
            rounds.get(setting)
            or rounds[
                next(s for s in timed if (s.hz, s.iterations) == (setting.hz, setting.iterations))
            ]
        )
        trial_s = statistics.median(t for t, _ in timing)
        commands = timing[0][1]
        gait_rows = {}
        for name, replay in replays[setting].items():
            ref = reference[name]
            gait_rows[name] = {
                "distance_m": replay.distance_m,
                "reference_m": ref.distance_m,
                "relative_error": abs(replay.distance_m - ref.distance_m)
                / max(abs(ref.distance_m), 1e-9),
                "failure": replay.failure,
                "reference_failure": ref.failure,
                "completed": replay.completed,
                "failure_changed": (replay.failure is None) != (ref.failure is None)
                or replay.completed != ref.completed,
            }
        rows.append(
            {
                "setting": setting.label,
                "hz": setting.hz,
                "iterations": setting.iterations,
                "settle_s": setting.settle_s,
                "trial_s": trial_s,
                "step_ms": 1000 * trial_s * len(gaits) / max(commands, 1),
                "gaits": gait_rows,
            }
        )
    return {"body": formation.name, "world": world.name, "rows": rows}


def copy_places(copies: int) -> list[tuple[float, float]]:
    """Where each copy stands (m): a square grid ``COPY_SPACING_M`` apart, centred on the
    origin, row by row."""
    side = math.ceil(math.sqrt(copies))
    centre = (side - 1) / 2
    places = [
        ((column - centre) * COPY_SPACING_M, (row - centre) * COPY_SPACING_M)
        for row in range(side)
        for column in range(side)
    ][:copies]
    if max(max(abs(x), abs(y)) for x, y in places) > GROUND_HALF_M:
        raise SystemExit(f"--copies: {copies} copies {COPY_SPACING_M:g} m apart leave the ground")
    return places


def copies_client(
    formation: Formation, postures: np.ndarray, physics: PhysicsSettings, copies: int, apart: bool
) -> tuple[BulletSimulation, list[int]]:
    """One client holding ``copies`` bodies (:func:`copy_places`); ``apart``
    takes each copy out of the others' collision filter (the ground stays in every one's)."""
    import pybullet  # the package has imported it quietly by now

    robot = assemble(formation)
    sim = BulletSimulation(robot=robot, settings=physics)
    sim.reset(formation.posture_rad(postures[-1]))
    client = sim.client
    position, orientation = client.getBasePositionAndOrientation(sim.body_id)
    places = copy_places(copies)
    client.resetBasePositionAndOrientation(sim.body_id, (*places[0], position[2]), orientation)
    flags = pybullet.URDF_USE_INERTIA_FROM_FILE
    if physics.self_collision:
        flags |= pybullet.URDF_USE_SELF_COLLISION | pybullet.URDF_USE_SELF_COLLISION_EXCLUDE_PARENT
    bodies = [sim.body_id]
    with tempfile.TemporaryDirectory(prefix="qdsega-copies-") as folder:
        urdf = Path(folder) / f"{formation.name}.urdf"
        write_assembly(robot, urdf)
        for x, y in places[1:]:
            at = (x, y, position[2])
            bodies.append(client.loadURDF(str(urdf), at, orientation, flags=flags))
    for body in bodies[1:]:
        for joint_id, angle in zip(sim.joint_ids, formation.posture_rad(postures[-1]), strict=True):
            client.resetJointState(body, int(joint_id), float(angle), 0.0)
        for unit in formation.units:
            client.changeDynamics(
                body,
                sim.link_index[unit.name],
                lateralFriction=unit.friction.lateral,
                anisotropicFriction=list(unit.friction.anisotropic),
            )
    if apart:
        for ground in sim.terrain.ground:
            client.setCollisionFilterGroupMask(ground, -1, 1, -1)
        for index, body in enumerate(bodies):
            group = 1 << (index + 1)
            for link in sim.link_index.values():
                client.setCollisionFilterGroupMask(body, link, group, 1 | group)
    return sim, bodies


def walk_copies(
    sim: BulletSimulation,
    bodies: list[int],
    postures: np.ndarray,
    physics_steps_per_posture: int,
    speeds: list[float],
) -> None:
    """Every copy commanded through ``postures`` in step, one posture per upper-agent step."""
    import pybullet

    client, formation = sim.client, sim.formation
    efforts = [joint.spec.effort_nm for joint in formation.joints]
    for levels in postures:
        targets = formation.posture_rad(levels)
        for body in bodies:
            for joint_id, target, effort, speed in zip(
                sim.joint_ids, targets, efforts, speeds, strict=True
            ):
                client.setJointMotorControl2(
                    body,
                    int(joint_id),
                    pybullet.POSITION_CONTROL,
                    targetPosition=float(target),
                    force=effort,
                    maxVelocity=speed,
                    positionGain=sim.settings.position_gain,
                )
        sim.step(physics_steps_per_posture)


def base_xy(sim: BulletSimulation, bodies: list[int]) -> np.ndarray:
    """Where each body's root unit stands, (bodies, 2) (m)."""
    return np.array([sim.client.getBasePositionAndOrientation(b)[0][:2] for b in bodies])


def measure_copies(
    formation: Formation, counts: list[int], seconds: float, repeats: int
) -> list[dict[str, Any]]:
    """Physics steps per second per body for each count of copies in one client, with the
    copies in each other's collision filter and out of it; interleaved rounds, the median."""
    physics = PhysicsSettings()
    lower = LowerAgentConfig()
    per_posture = round(lower.step_duration_for(formation) / physics.time_step_s)
    steps = max(1, round(seconds / lower.step_duration_for(formation)))
    postures = classic_gaits.default_gait(formation, steps=steps)
    speeds = [min(j.spec.velocity_rad_s, lower.joint_speed_rad_s) for j in formation.joints]
    cases = [(n, apart) for n in counts for apart in ((False,) if n == 1 else (False, True))]
    clients = {case: copies_client(formation, postures, physics, *case) for case in cases}
    rates: dict[tuple[int, bool], list[float]] = {case: [] for case in cases}
    starts = {case: base_xy(*clients[case]) for case in cases}
    try:
        for round_index in range(repeats):
            turn = round_index % len(cases)
            for case in cases[turn:] + cases[:turn]:
                sim, bodies = clients[case]
                start = time.perf_counter()
                walk_copies(sim, bodies, postures, per_posture, speeds)
                wall = time.perf_counter() - start
                rates[case].append(len(bodies) * len(postures) * per_posture / wall)
        touching = {
            case: sum(
                len(sim.client.getContactPoints(bodyA=a, bodyB=b))
                for a, b in itertools.combinations(bodies, 2)
            )
            for case, (sim, bodies) in clients.items()
        }
        walked = {
            case: np.linalg.norm(base_xy(*clients[case]) - starts[case], axis=1) for case in cases
        }
    finally:
        for sim, _ in clients.values():
            sim.close()
    single = statistics.median(rates[(1, False)]) if (1, False) in rates else float("nan")
    return [
        {
            "body": formation.name,
            "copies": n,
            "filtered_apart": apart,
            "steps_per_s_per_body": statistics.median(rates[(n, apart)]),
            "vs_one": statistics.median(rates[(n, apart)]) / single,
            "contacts_between_copies": touching[(n, apart)],
            "walked_m": walked[(n, apart)].tolist(),
        }
        for n, apart in cases
    ]


def worst_error(row: dict[str, Any]) -> float | None:
    """The largest relative distance error among the gaits that complete under the reference
    physics (None when none does: a failing gait's distance is a step or two's)."""
    errors = [g["relative_error"] for g in row["gaits"].values() if g["reference_failure"] is None]
    return max(errors, default=None)


def changed_failures(row: dict[str, Any]) -> int:
    """Gaits whose failing, or the step it fails at, differs from the reference physics'."""
    return sum(g["failure_changed"] for g in row["gaits"].values())


def steady_gaits(result: dict[str, Any], tolerance: float) -> list[str]:
    """The gaits whose outcome the reference physics itself holds when only the start moves:
    at every other settle time of the reference rate and iterations, the failure (and its
    step) unchanged and the distance within ``tolerance`` of the reference's."""
    first = result["rows"][0]
    moved = [
        row
        for row in result["rows"][1:]
        if (row["hz"], row["iterations"]) == (first["hz"], first["iterations"])
    ]
    return [
        name
        for name in first["gaits"]
        if all(
            not row["gaits"][name]["failure_changed"]
            and row["gaits"][name]["relative_error"] <= tolerance
            for row in moved
        )
    ]


def print_steady(results: list[dict[str, Any]], tolerance: float) -> None:
    """Per physics setting at the reference settle time: 'ok' where every steady gait keeps
    its failure and its distance within ``tolerance``, else the worst error (of the steady
    gaits that complete under the reference) and the failures changed."""
    steady = [steady_gaits(result, tolerance) for result in results]
    print(
        f"Steady gaits (at every other settle time of the reference physics: failure as it "
        f"was, distance within {tolerance:.0%}); per setting: ok where every steady gait keeps "
        f"its failure and its distance within {tolerance:.0%}, else the worst error and the "
        f"failures changed"
    )
    for result, names in zip(results, steady, strict=True):
        print(f"- {result['body']} {result['world']}: {', '.join(names) or 'none'}")
    columns = [
        f"{r['body']} {r['world']} ({len(names)} of {len(r['rows'][0]['gaits'])})"
        for r, names in zip(results, steady, strict=True)
    ]
    print(f"| setting | {' | '.join(columns)} |")
    print(f"|---|{'---|' * len(columns)}")
    settle = results[0]["rows"][0]["settle_s"]
    for index, row in enumerate(results[0]["rows"]):
        if row["settle_s"] != settle:
            continue
        cells = []
        for result, names in zip(results, steady, strict=True):
            gaits = [result["rows"][index]["gaits"][name] for name in names]
            errors = [g["relative_error"] for g in gaits if g["reference_failure"] is None]
            worst = max(errors, default=0.0)
            changed = sum(g["failure_changed"] for g in gaits)
            text = f"{worst:.1%}" if errors else "-"
            if not names:
                cells.append("-")
            elif worst <= tolerance and not changed:
                cells.append(f"ok ({text})")
            else:
                cells.append(text + (f", {changed} F" if changed else ""))
        print(f"| {row['setting']} | {' | '.join(cells)} |")


def print_fidelity(results: list[dict[str, Any]]) -> None:
    print("Reference gaits, default physics (F: the lower agent failed):")
    print("| body | world | gait | distance (m) | postures reached | failure |")
    print("|---|---|---|---|---|---|")
    for result in results:
        for name, gait in result["rows"][0]["gaits"].items():
            print(
                f"| {result['body']} | {result['world']} | {name} | {gait['distance_m']:.3f} "
                f"| {gait['completed']} | {gait['failure'] or '-'} |"
            )
    print()
    print("Every setting (Hz : solver iterations : settle s); distances per gait in the order")
    print("above, F<k>: failed after k postures; error: |d - d_ref| / |d_ref|, worst gait that")
    print("completes under the default; failures: gaits whose failing or its step changed;")
    print("wall time: the median round; speed-up: per upper-agent step, against the default")
    print(
        "| body | world | setting | distances (m) | worst error | failures "
        "| wall s / trial | ms / step | speed-up |"
    )
    print("|---|---|---|---|---|---|---|---|---|")
    for result in results:
        base_ms = result["rows"][0]["step_ms"]
        for row in result["rows"]:
            distances = " / ".join(
                f"{g['distance_m']:.3f}" + (f"F{g['completed']}" if g["failure"] else "")
                for g in row["gaits"].values()
            )
            error = worst_error(row)
            print(
                f"| {result['body']} | {result['world']} | {row['setting']} | {distances} "
                f"| {'-' if error is None else f'{error:.1%}'} | {changed_failures(row)} "
                f"| {row['trial_s']:.2f} | {row['step_ms']:.1f} | {base_ms / row['step_ms']:.2f}x |"
            )
    print()
    print("In short: worst error, and failures changed where any (a dash: no gait completes);")
    print("speed-up per upper-agent step, median over the worlds")
    bodies = list(dict.fromkeys(r["body"] for r in results))
    columns = [f"{r['body']} {r['world']}" for r in results]
    print(f"| setting | {' | '.join(columns)} | {' | '.join(f'{b} speed-up' for b in bodies)} |")
    print(f"|---|{'---|' * (len(columns) + len(bodies))}")
    for index, row in enumerate(results[0]["rows"]):
        cells = []
        for result in results:
            cell_row = result["rows"][index]
            error, changed = worst_error(cell_row), changed_failures(cell_row)
            text = "-" if error is None else f"{error:.1%}"
            cells.append(text + (f", {changed} F" if changed else ""))
        for body in bodies:
            ups = [
                r["rows"][0]["step_ms"] / r["rows"][index]["step_ms"]
                for r in results
                if r["body"] == body
            ]
            cells.append(f"{statistics.median(ups):.2f}x")
        print(f"| {row['setting']} | {' | '.join(cells)} |")


def print_copies(copies: list[dict[str, Any]]) -> None:
    print("Copies in one client (default physics, flat ground, 90 m apart):")
    print(
        "| body | copies | out of each other's filter | physics steps/s per body "
        "| vs one body per client | contacts between copies | each copy walked (m) |"
    )
    print("|---|---|---|---|---|---|---|")
    for row in copies:
        print(
            f"| {row['body']} | {row['copies']} | {'yes' if row['filtered_apart'] else 'no'} "
            f"| {row['steps_per_s_per_body']:.0f} | {row['vs_one']:.2f}x "
            f"| {row['contacts_between_copies']} "
            f"| {' / '.join(f'{w:.3f}' for w in row['walked_m'])} |"
        )


def print_all(
    results: list[dict[str, Any]], copies: list[dict[str, Any]], tolerance: float
) -> None:
    if results:
        print_fidelity(results)
        print()
        print_steady(results, tolerance)
        print()
    if copies:
        print_copies(copies)
        print()


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--bodies", default="quadruped,legged12,snake5")
    parser.add_argument("--worlds", default="flat,slope,rubble", help="'' for the copies only")
    parser.add_argument(
        "--hz", default="240,120,60", help="physics rates; the first is the reference"
    )
    parser.add_argument(
        "--iterations", default="50,20,10", help="solver iterations; first: reference"
    )
    parser.add_argument("--settle", default="0.5,0.25,1", help="settle times (s); first: reference")
    parser.add_argument("--tolerance", type=float, default=0.05, help="relative distance error")
    parser.add_argument("--steps", type=int, default=30, help="upper-agent steps per trial")
    parser.add_argument("--repeats", type=int, default=3, help="timed rounds (median kept)")
    parser.add_argument("--copies", default="1,2,4", help="bodies per client ('' to skip)")
    parser.add_argument("--copy-seconds", type=float, default=5.0, help="simulated s per round")
    parser.add_argument("--copy-repeats", type=int, default=5, help="rounds of the copies")
    parser.add_argument("--json", type=Path, help="write every measurement here")
    parser.add_argument("--tables", type=Path, help="print the tables of a --json file only")
    args = parser.parse_args()
    if min(args.steps, args.repeats, args.copy_repeats) < 1:
        parser.error("--steps, --repeats and --copy-repeats must be at least 1")
    if not (args.copy_seconds > 0 and args.tolerance > 0):
        parser.error("--copy-seconds and --tolerance must be positive")
    settings = [
        Setting(hz=hz, iterations=iterations, settle_s=settle)
        for settle, hz, iterations in itertools.product(
            number_list(args.settle, float, "settle"),
            number_list(args.hz, float, "hz"),
            number_list(args.iterations, int, "iterations"),
        )
    ]
    if args.tables:
        saved = json.loads(args.tables.read_text(encoding="utf-8"))
        print_all(saved["fidelity"], saved["copies"], args.tolerance)
        return 0
    counts = number_list(args.copies, int, "copies") if args.copies else []
    formations = [load_formation(resolve_formation(b)) for b in args.bodies.split(",")]
    worlds = [named_world(w) for w in args.worlds.split(",")] if args.worlds else []
    start = time.perf_counter()
    results = []
    for formation, world in itertools.product(formations, worlds):
        results.append(measure_body_world(formation, world, settings, args.steps, args.repeats))
        print(
            f"{formation.name} {world.name}: {time.perf_counter() - start:.0f} s", file=sys.stderr
        )
    copies = [
        row
        for formation in formations
        if counts
        for row in measure_copies(formation, counts, args.copy_seconds, args.copy_repeats)
    ]
    print_all(results, copies, args.tolerance)
    print(f"{time.perf_counter() - start:.0f} s in all; wall times are relative only")
    if args.json:
        args.json.write_text(json.dumps({"fidelity": results, "copies": copies}, indent=1))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
