"""Can the shipped snakes climb the shipped slope? The best gaits of several kinds, exact physics.

Usage: .venv/bin/python experiments/snake_slope/run.py [--quick] [--bodies snake5,snake10]
           [--stages references,wide,headings,angles,flat_gait] [--angles 0,2,4,6,8]
           [--cma-trials 600] [--short-cma-trials 66] [--cycles 2,3,4,6,8] [--offsets 0,5,10]
           [--steps 30] [--json OUT.json]
       .venv/bin/python experiments/snake_slope/run.py --tables OUT.json [MORE.json ...]

Every trial is one episode of ``LocomotionEnv`` (the env learning, evaluation and the
reference search use; default rules: 30 commands, the lower agent's derived step, 240 Hz), a
posture sequence played open loop by ``replay_postures``; a distance is the body's gain
toward the light (+x, where ``slope`` rises). Stages:

- ``references``: on the shipped ``slope`` (8 deg), the body at rest (its start posture held),
  the default serpenoid, the best of ``qdsega evaluate``'s serpenoid grid (45 candidates), and
  the CMA-ES CPG reference of ``--cma-trials`` trials (``reference_gait``: the same search
  and cache key as ``qdsega evaluate`` on a snake run in ``slope``; searched once, then read
  from the cache); also the CPG gait the package ships for flat ground.
- ``wide``: a wider serpenoid grid on ``slope``: amplitude, phase lag, steps per cycle and a
  constant turning offset on every joint (a serpenoid written as a ``CPGGait``).
- ``headings``: the body at rest and the best gait found so far, with the slope rising toward
  0, 45, 90, 135 and 180 deg from the start heading (the light stays ahead): distance toward
  the light and the body's world displacement up the fall line.
- ``angles``: worlds of 0..8 deg rising toward the light (YAML, ``ground: {slope: ...}``): the
  body at rest, the serpenoid grid's best and a CMA-ES CPG search (``--short-cma-trials``
  trials; where a ``--cma-trials`` search is cached, as on flat and at 8 deg, that one too).
- ``flat_gait``: the CMA-ES gait the package ships for flat ground, replayed at every angle
  (one trial each).

``--quick`` shrinks every stage to seconds (snake5, 0 and 8 deg, one CMA-ES generation, a
two-gait wide grid), to check that the script runs.
"""

from __future__ import annotations

import argparse
import itertools
import json
import math
import sys
import tempfile
import time
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

import numpy as np

from qdsega.baselines import classic_gaits
from qdsega.baselines.cpg import CPGGait
from qdsega.baselines.reference_search import (
    SHIPPED_DIR,
    check_budget,
    reference_gait,
    reference_key,
    user_cache_dir,
)
from qdsega.description import Formation, World, load_formation, load_world, resolve_formation
from qdsega.locomotion.env import LocomotionEnv, replay_postures, rules_env
from qdsega.locomotion.rules import ExactRules
from qdsega.task import TaskConfig

STAGES = ("references", "wide", "headings", "angles", "flat_gait")
SLOPE_DEG = 8.0
"""The shipped ``slope`` world's angle (deg)."""
HEADINGS_DEG = (0, 45, 90, 135, 180)
"""Bearings the slope rises toward, from the start heading, in the ``headings`` stage (deg)."""


@dataclass(frozen=True)
class WideGrid:
    """The wider serpenoid grid: every combination of these (deg, deg, steps, deg)."""

    amplitudes_deg: tuple[float, ...] = (10.0, 20.0, 30.0)
    lags_deg: tuple[float, ...] = (30.0, 60.0, 90.0, 120.0, 150.0, 180.0)
    cycles: tuple[int, ...] = (2, 3, 4, 6, 8)
    offsets_deg: tuple[float, ...] = (0.0, 5.0, 10.0)


QUICK_GRID = WideGrid(amplitudes_deg=(20.0,), lags_deg=(60.0,), cycles=(4,), offsets_deg=(0, 5))


def slope_world(folder: Path, angle_deg: float, toward_deg: float = 0.0) -> World:
    """A world whose ground rises at ``angle_deg`` toward ``toward_deg``, written as YAML in
    ``folder`` and read back as any world file is."""
    name = f"slope-{angle_deg:g}deg-toward-{toward_deg:g}"
    file = folder / f"{name}.yaml"
    file.write_text(
        f"name: {name}\nground:\n"
        f"  slope: {{angle_deg: {angle_deg:g}, toward_deg: {toward_deg:g}}}\n",
        encoding="utf-8",
    )
    return load_world(file)


def serpenoid_cpg(
    formation: Formation, *, amplitude_deg: float, lag_deg: float, cycle: int, offset_deg: float
) -> CPGGait:
    """The serpenoid ``offset + A sin(2 pi k / N - i lag)`` of joint ``i`` as a CPG gait (the
    same wave as ``classic_gaits.serpenoid``, plus a constant offset that bends the body)."""
    joints = len(formation.joints)
    return CPGGait(
        amplitude_rad=(math.radians(amplitude_deg),) * joints,
        offset_rad=(math.radians(offset_deg),) * joints,
        phase_rad=tuple(-i * math.radians(lag_deg) for i in range(joints)),
        period_steps=cycle,
    )


class Trials:
    """Exact trials of one body in one world: distance toward the light, failure, and the
    world displacement up the fall line."""

    def __init__(self, formation: Formation, world: World, steps: int) -> None:
        self.formation = world.lights(formation)
        self.world = world
        self.rules = ExactRules(task=TaskConfig(trial_steps=steps), world=world)
        self.env: LocomotionEnv = rules_env(self.formation, self.rules)
        self.env.reset(seed=0)
        self.start = self.env.lower_agent.pose().planar
        self.count = 0

    def play(self, postures: np.ndarray) -> dict[str, Any]:
        """One trial of ``postures`` (steps, J) from the settled start."""
        replay = replay_postures(self.env, postures)
        self.count += 1
        x, y, _ = self.env.lower_agent.pose().planar
        toward = self.world.slope_toward_rad
        uphill = (x - self.start[0]) * math.cos(toward) + (y - self.start[1]) * math.sin(toward)
        return {
            "distance_m": replay.distance_m,
            "uphill_m": uphill,
            "completed": replay.completed,
            "failure": replay.failure,
        }

    def rest(self) -> dict[str, Any]:
        """The start posture held for a whole trial: how far the body slides doing nothing."""
        steps = self.rules.task.trial_steps
        return self.play(np.tile(np.array(self.formation.rest_levels()), (steps, 1)))

    def start_heading_deg(self) -> float:
        """The settled start's heading from the slope's rise (deg, in (-180, 180])."""
        turn = self.start[2] - self.world.slope_toward_rad
        return math.degrees(math.atan2(math.sin(turn), math.cos(turn)))

    def close(self) -> None:
        self.env.close()


def best_of(rows: list[dict[str, Any]]) -> dict[str, Any] | None:
    """The row that went farthest toward the light without failing (None: every one failed)."""
    done = [r for r in rows if r["failure"] is None]
    return max(done, key=lambda r: r["distance_m"]) if done else None


def summary(rows: list[dict[str, Any]]) -> dict[str, Any]:
    """Best row, how many were tried, failed and gained ground."""
    return {
        "best": best_of(rows),
        "tried": len(rows),
        "failed": sum(r["failure"] is not None for r in rows),
        "climbed": sum(r["failure"] is None and r["distance_m"] > 0 for r in rows),
    }


def serpenoid_grid(trials: Trials) -> dict[str, Any]:
    """``qdsega evaluate``'s serpenoid grid (``classic_gaits.serpenoid_grid``), every
    candidate's distance kept (the evaluator counts a gait that goes backward as 0 m)."""
    steps = trials.rules.task.trial_steps
    rows = [
        {"params": params, **trials.play(postures)}
        for params, postures in classic_gaits.serpenoid_grid(trials.formation, steps=steps)
    ]
    return summary(rows)


def wide_grid(trials: Trials, grid: WideGrid) -> dict[str, Any]:
    """Every serpenoid of ``grid`` (with its turning offset)."""
    steps = trials.rules.task.trial_steps
    rows = []
    for amplitude, lag, cycle, offset in itertools.product(
        grid.amplitudes_deg, grid.lags_deg, grid.cycles, grid.offsets_deg
    ):
        params = {
            "amplitude_deg": amplitude,
            "phase_lag_deg": lag,
            "steps_per_cycle": cycle,
            "offset_deg": offset,
        }
        gait = serpenoid_cpg(
            trials.formation, amplitude_deg=amplitude, lag_deg=lag, cycle=cycle, offset_deg=offset
        )
        rows.append({"params": params, **trials.play(gait.postures(trials.formation, steps=steps))})
    result = summary(rows)
    result["top"] = sorted(
        (r for r in rows if r["failure"] is None), key=lambda r: -r["distance_m"]
    )[:5]
    return result


def is_cached(formation: Formation, rules: ExactRules, budget: int) -> bool:
    """Whether the CMA-ES reference of ``budget`` trials is shipped or in the user cache."""
    name = f"{formation.name}-{reference_key(formation, rules=rules, budget_trials=budget)[:16]}"
    return any((folder / f"{name}.json").is_file() for folder in (SHIPPED_DIR, user_cache_dir()))


def cma_reference(trials: Trials, budget: int) -> dict[str, Any]:
    """The CMA-ES CPG reference of ``budget`` trials (cached, else searched on one process),
    replayed in ``trials``' env; its parameters and the search's own distance."""
    check_budget(trials.formation, budget)
    start = time.perf_counter()
    try:
        found = reference_gait(
            trials.formation, rules=trials.rules, budget_trials=budget, workers=1
        )
    except ValueError as exc:  # no trial completed
        return {"budget_trials": budget, "error": str(exc), "failure": "no trial completed"}
    return {
        "budget_trials": budget,
        "search_m": found.distance_m,
        "params": found.params.to_dict(),
        "history_m": list(found.history_m),
        "wall_s": time.perf_counter() - start,
        "cache": str(found.file),
        **trials.play(found.postures),
    }


def flat_cpg_on(trials: Trials, budget: int) -> dict[str, Any] | None:
    """The CPG gait searched on flat ground (shipped with the package), played here; None
    where it is not shipped (then it would search)."""
    flat = replace(trials.rules, world=World())
    if not is_cached(trials.formation, flat, budget):
        return None
    found = reference_gait(trials.formation, rules=flat, budget_trials=budget, workers=1)
    return {
        "params": found.params.to_dict(),
        "flat_m": found.distance_m,
        **trials.play(found.postures),
    }


def gait_postures(formation: Formation, row: dict[str, Any], steps: int) -> np.ndarray:
    """The postures of a serpenoid row (with or without an offset) or a CPG row."""
    params = row["params"]
    if "period_steps" in params:
        return CPGGait.from_dict(params).postures(formation, steps=steps)
    gait = serpenoid_cpg(
        formation,
        amplitude_deg=params["amplitude_deg"],
        lag_deg=params["phase_lag_deg"],
        cycle=params["steps_per_cycle"],
        offset_deg=params.get("offset_deg", 0.0),
    )
    return gait.postures(formation, steps=steps)


def stage_references(formation: Formation, folder: Path, steps: int, budget: int) -> dict[str, Any]:
    trials = Trials(formation, slope_world(folder, SLOPE_DEG), steps)
    try:
        return {
            "start_heading_deg": trials.start_heading_deg(),
            "rest": trials.rest(),
            "default_serpenoid": trials.play(
                classic_gaits.default_gait(trials.formation, steps=steps)
            ),
            "serpenoid_grid": serpenoid_grid(trials),
            "cma": cma_reference(trials, budget),
            "flat_cpg": flat_cpg_on(trials, budget),
            "trials": trials.count,
        }
    finally:
        trials.close()


def stage_wide(formation: Formation, folder: Path, steps: int, grid: WideGrid) -> dict[str, Any]:
    trials = Trials(formation, slope_world(folder, SLOPE_DEG), steps)
    try:
        return wide_grid(trials, grid)
    finally:
        trials.close()


def best_gait(body: dict[str, Any]) -> dict[str, Any] | None:
    """The best gait on the 8 deg slope among what the references and wide stages found."""
    rows = []
    if "references" in body:
        refs = body["references"]
        rows += [r for r in (refs["serpenoid_grid"]["best"], refs["cma"]) if r and "params" in r]
    if "wide" in body and body["wide"]["best"] is not None:
        rows.append(body["wide"]["best"])
    return best_of(rows)


def stage_headings(
    formation: Formation, folder: Path, steps: int, gait: dict[str, Any] | None
) -> list[dict[str, Any]]:
    rows = []
    for toward in HEADINGS_DEG:
        trials = Trials(formation, slope_world(folder, SLOPE_DEG, toward), steps)
        try:
            row = {
                "toward_deg": toward,
                "start_heading_deg": trials.start_heading_deg(),
                "rest": trials.rest(),
            }
            if gait is not None:
                row["gait"] = trials.play(gait_postures(trials.formation, gait, steps))
            rows.append(row)
        finally:
            trials.close()
    return rows


def stage_angles(
    formation: Formation,
    folder: Path,
    steps: int,
    angles: list[float],
    short_budget: int,
    budget: int,
    done: dict[str, Any] | None,
) -> list[dict[str, Any]]:
    """Per angle: rest, the serpenoid grid's best, the short CMA-ES search, and the
    ``budget`` one where cached (at ``SLOPE_DEG`` the references stage's results are reused)."""
    rows = []
    for angle in angles:
        started = time.perf_counter()
        trials = Trials(formation, slope_world(folder, angle), steps)
        try:
            row: dict[str, Any] = {"angle_deg": angle}
            if angle == SLOPE_DEG and done is not None:
                row["rest"], row["serpenoid_grid"] = done["rest"], done["serpenoid_grid"]
                row["cma_long"] = done["cma"]
            else:
                row["rest"] = trials.rest()
                row["serpenoid_grid"] = serpenoid_grid(trials)
                if is_cached(trials.formation, trials.rules, budget):
                    row["cma_long"] = cma_reference(trials, budget)
            if short_budget != budget:
                row["cma_short"] = cma_reference(trials, short_budget)
            row["wall_s"] = time.perf_counter() - started
            rows.append(row)
        finally:
            trials.close()
        print(f"  {formation.name} {angle:g} deg: {row['wall_s']:.0f} s", file=sys.stderr)
    return rows


def stage_flat_gait(
    formation: Formation, folder: Path, steps: int, angles: list[float], budget: int
) -> list[dict[str, Any]]:
    """The CMA-ES gait searched on flat ground (shipped), replayed at every angle."""
    rows = []
    for angle in angles:
        trials = Trials(formation, slope_world(folder, angle), steps)
        try:
            rows.append({"angle_deg": angle, "flat_cpg": flat_cpg_on(trials, budget)})
        finally:
            trials.close()
    return rows


# -- tables ------------------------------------------------------------------------------------


def metres(row: dict[str, Any] | None) -> str:
    """A trial's distance, or why it has none (F<k>: failed after k commands)."""
    if row is None:
        return "-"
    if row.get("failure") is not None:
        if "distance_m" not in row:
            return "none completed"
        return f"{row['distance_m']:.3f} F{row['completed']}"
    return f"{row['distance_m']:.3f}"


def serpenoid_label(params: dict[str, Any]) -> str:
    text = (
        f"{params['amplitude_deg']:.0f}/{params['phase_lag_deg']:.0f}/{params['steps_per_cycle']}"
    )
    return text + (f"/{params['offset_deg']:+.0f}" if "offset_deg" in params else "")


def grid_cell(grid: dict[str, Any]) -> str:
    best = grid["best"]
    label = "-" if best is None else f"{metres(best)} ({serpenoid_label(best['params'])})"
    return f"{label}; {grid['climbed']} of {grid['tried']} > 0, {grid['failed']} failed"


def print_tables(results: dict[str, Any]) -> None:
    bodies = results["bodies"]
    if any("references" in b for b in bodies.values()):
        print(f"1. References on slope ({SLOPE_DEG:g} deg), distance toward the light (m)")
        print(
            "| body | at rest | default serpenoid | serpenoid grid best (A/lag/N); "
            "gaining, failed | CMA-ES CPG (trials) | flat CPG gait here |"
        )
        print("|---|---|---|---|---|---|")
        for name, body in bodies.items():
            refs = body.get("references")
            if refs is None:
                continue
            cma = refs["cma"]
            print(
                f"| {name} | {metres(refs['rest'])} | {metres(refs['default_serpenoid'])} "
                f"| {grid_cell(refs['serpenoid_grid'])} "
                f"| {metres(cma)} ({cma['budget_trials']}) | {metres(refs['flat_cpg'])} |"
            )
        print()
    if any("wide" in b for b in bodies.values()):
        print("2. Wide serpenoid grid on slope (A/lag/N/offset), distance toward the light (m)")
        print("| body | best; gaining, failed | next four |")
        print("|---|---|---|")
        for name, body in bodies.items():
            wide = body.get("wide")
            if wide is None:
                continue
            others = ", ".join(
                f"{metres(r)} ({serpenoid_label(r['params'])})" for r in wide["top"][1:]
            )
            print(f"| {name} | {grid_cell(wide)} | {others or '-'} |")
        print()
    if any("headings" in b for b in bodies.values()):
        print("2b. Slope rising toward a bearing from the start heading (light ahead):")
        print("    distance toward the light / displacement up the fall line (m)")
        print(
            "| body | rises toward (deg) | settled heading from the rise (deg) "
            "| at rest | best gait |"
        )
        print("|---|---|---|---|---|")
        for name, body in bodies.items():
            for row in body.get("headings", []):
                gait = row.get("gait")
                gait_text = "-" if gait is None else f"{metres(gait)} / {gait['uphill_m']:+.3f}"
                print(
                    f"| {name} | {row['toward_deg']} | {row['start_heading_deg']:+.0f} "
                    f"| {metres(row['rest'])} / {row['rest']['uphill_m']:+.3f} | {gait_text} |"
                )
        print()
    if any("angles" in b for b in bodies.values()):
        print("3. Slope angle (rising toward the light), distance toward the light (m)")
        print(
            "| body | angle (deg) | at rest | serpenoid grid best; gaining, failed "
            "| CMA-ES short (trials) | CMA-ES long (trials) | best |"
        )
        print("|---|---|---|---|---|---|---|")
        for name, body in bodies.items():
            for row in body.get("angles", []):
                cells = []
                for key in ("cma_short", "cma_long"):
                    cma = row.get(key)
                    cells.append("-" if cma is None else f"{metres(cma)} ({cma['budget_trials']})")
                best = best_of(
                    [
                        r
                        for r in (
                            row["serpenoid_grid"]["best"],
                            row.get("cma_short"),
                            row.get("cma_long"),
                        )
                        if r is not None and "distance_m" in r
                    ]
                )
                print(
                    f"| {name} | {row['angle_deg']:g} | {metres(row['rest'])} "
                    f"| {grid_cell(row['serpenoid_grid'])} | {cells[0]} | {cells[1]} "
                    f"| {metres(best)} |"
                )
        print()
    if any("flat_gait" in b for b in bodies.values()):
        print_flat_gait(bodies)


def print_flat_gait(bodies: dict[str, Any]) -> None:
    print("3b. The CMA-ES gait searched on flat ground (shipped, 600 trials) at each angle (m)")
    names = [name for name, body in bodies.items() if "flat_gait" in body]
    angles = sorted({row["angle_deg"] for name in names for row in bodies[name]["flat_gait"]})
    print(f"| body | {' | '.join(f'{a:g} deg' for a in angles)} |")
    print(f"|---|{'---|' * len(angles)}")
    for name in names:
        found = {row["angle_deg"]: row["flat_cpg"] for row in bodies[name]["flat_gait"]}
        print(f"| {name} | {' | '.join(metres(found.get(a)) for a in angles)} |")
    print()


def number_list(text: str, name: str) -> list[float]:
    try:
        return [float(v) for v in text.split(",")]
    except ValueError:
        raise SystemExit(f"--{name}: {text!r} is not a comma-separated list of numbers") from None


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="seconds: check that it runs")
    parser.add_argument("--bodies", default="snake5,snake10")
    parser.add_argument("--stages", default=",".join(STAGES))
    parser.add_argument("--angles", default="0,2,4,6,8", help="slope angles (deg), stage angles")
    parser.add_argument("--cma-trials", type=int, default=600, help="the references' CMA-ES budget")
    parser.add_argument("--short-cma-trials", type=int, default=66, help="CMA-ES at each angle")
    parser.add_argument("--steps", type=int, default=30, help="commands per trial")
    parser.add_argument("--json", type=Path, help="write every measurement here (after each stage)")
    parser.add_argument("--cycles", default="2,3,4,6,8", help="wide grid: steps per cycle")
    parser.add_argument("--offsets", default="0,5,10", help="wide grid: turning offsets (deg)")
    parser.add_argument(
        "--tables", type=Path, nargs="+", help="print the tables of --json files only"
    )
    args = parser.parse_args()
    if args.tables:
        merged: dict[str, Any] = {"bodies": {}}
        for file in args.tables:  # a later file's angles join an earlier one's
            for name, body in json.loads(file.read_text(encoding="utf-8"))["bodies"].items():
                kept = merged["bodies"].setdefault(name, {})
                joined = {
                    stage: kept.get(stage, []) + body.get(stage, [])
                    for stage in ("angles", "flat_gait")
                }
                kept.update(body)
                for stage, rows in joined.items():
                    if rows:
                        kept[stage] = sorted(rows, key=lambda row: row["angle_deg"])
        print_tables(merged)
        return 0
    stages = args.stages.split(",")
    if unknown := set(stages) - set(STAGES):
        parser.error(f"--stages: unknown {sorted(unknown)}; choose from {', '.join(STAGES)}")
    if args.steps < 1:
        parser.error("--steps must be at least 1")
    grid = WideGrid(
        cycles=tuple(int(c) for c in number_list(args.cycles, "cycles")),
        offsets_deg=tuple(number_list(args.offsets, "offsets")),
    )
    angles = number_list(args.angles, "angles")
    bodies = args.bodies.split(",")
    formations = [load_formation(resolve_formation(b)) for b in bodies]
    if args.quick:
        grid, angles, formations = QUICK_GRID, [0.0, SLOPE_DEG], formations[:1]
    results: dict[str, Any] = {"steps": args.steps, "bodies": {}}
    start = time.perf_counter()
    with tempfile.TemporaryDirectory() as temp:
        folder = Path(temp)
        for formation in formations:
            short = args.short_cma_trials
            budget = args.cma_trials
            if args.quick:  # one CMA-ES generation
                budget = short = 4 + int(3 * math.log(3 * len(formation.joints) + 1))
            body: dict[str, Any] = results["bodies"].setdefault(formation.name, {})
            for stage in stages:
                if stage == "references":
                    body[stage] = stage_references(formation, folder, args.steps, budget)
                elif stage == "wide":
                    body[stage] = stage_wide(formation, folder, args.steps, grid)
                elif stage == "headings":
                    body[stage] = stage_headings(formation, folder, args.steps, best_gait(body))
                elif stage == "flat_gait":
                    body[stage] = stage_flat_gait(formation, folder, args.steps, angles, budget)
                else:
                    body[stage] = stage_angles(
                        formation, folder, args.steps, angles, short, budget, body.get("references")
                    )
                print(
                    f"{formation.name} {stage}: {time.perf_counter() - start:.0f} s",
                    file=sys.stderr,
                    flush=True,
                )
                if args.json:
                    args.json.write_text(json.dumps(results, indent=1), encoding="utf-8")
    print_tables(results)
    print(f"{time.perf_counter() - start:.0f} s in all")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
