"""Screen settings of the open choices on the MSM: greedy/optimum per seed, in-process.

Usage: taskset -c 1 .venv/bin/python experiments/msm/sweep_msm.py [--formation FILE]
           --seeds 0 1 --generations 60 --set agent.fitness.k_f=10 --set msm.v=0.25 [--show-gait]

Each ``--set KEY=VALUE`` (VALUE parsed as YAML) overrides the paper-legged preset through
:func:`qdsega.training.config.resolve_config`, like a YAML override file. The learner runs on
the MSM in-process, without a run folder. Prints, per seed, the greedy distance over the MSM's
optimum at the last generation, the best generation, the number of actions, the final heading
and ten marks of the history, then the count of seeds at >= 0.95.
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path
from typing import Any

import numpy as np
import yaml

from qdsega.agent.learner import QDSEGA
from qdsega.description import load_formation
from qdsega.description.shipped import ASSEMBLIES_DIR
from qdsega.msm import LegLayout, MinimalSimulationModel, msm_optimum
from qdsega.task import Task
from qdsega.training.config import resolve_config
from qdsega.training.run import budget_overrides


def _nest(assignments: list[str]) -> dict[str, Any]:
    """``["a.b=1"]`` -> ``{"a": {"b": 1}}`` (values parsed as YAML)."""
    tree: dict[str, Any] = {}
    for item in assignments:
        key, _, value = item.partition("=")
        *parents, leaf = key.split(".")
        node = tree
        for part in parents:
            node = node.setdefault(part, {})
        node[leaf] = yaml.safe_load(value)
    return tree


def _merge(a: dict[str, Any], b: dict[str, Any]) -> dict[str, Any]:
    """``a`` updated by ``b``, nested mappings merged."""
    out = dict(a)
    for key, value in b.items():
        out[key] = _merge(out[key], value) if isinstance(value, dict) and key in out else value
    return out


def run_seed(formation_file: Path, overrides: dict[str, Any], show_gait: bool) -> dict[str, Any]:
    """Learn one run on the MSM with the preset (paper-legged unless ``overrides`` names one)
    updated by ``overrides``."""
    config = resolve_config(overrides=overrides)
    formation = config.with_light(load_formation(formation_file))
    layout = LegLayout.from_formation(formation)
    model = MinimalSimulationModel(legs=layout, params=config.msm)
    task = Task(config=config.task, light_xy=formation.light.position_m)
    optimum = msm_optimum(model, steps=task.trial_steps, light_xy=tuple(task.light))
    learner = QDSEGA(
        config=config.agent,
        levels=np.array([len(j.levels_rad) for j in formation.joints]),
        model=model,
        task=task,
        rng=np.random.default_rng(config.seed),
    )
    start = time.perf_counter()
    history = []
    for last in learner.run():
        history.append(last.greedy.distance_m / optimum.bound_m)
    result = {
        "ratio": history[-1],
        "best": max(history),
        "actions": last.space.n_actions,
        "heading_deg": float(np.degrees(last.greedy.poses[-1, 2])),
        "wall_s": time.perf_counter() - start,
        "history": history,
    }
    if show_gait:
        result["gait"] = layout.states(last.greedy.postures)
    return result


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--formation", type=Path, default=ASSEMBLIES_DIR / "legged12.yaml")
    parser.add_argument("--seeds", type=int, nargs="+", default=[0, 1])
    parser.add_argument("--generations", type=int)
    parser.add_argument("--trials", type=int)
    parser.add_argument("--set", dest="sets", action="append", default=[], metavar="KEY=VALUE")
    parser.add_argument("--show-gait", action="store_true")
    args = parser.parse_args()
    ratios = []
    for seed in args.seeds:
        base = budget_overrides(generations=args.generations, trials=args.trials, seed=seed)
        r = run_seed(args.formation, _merge(base, _nest(args.sets)), args.show_gait)
        ratios.append(r["ratio"])
        marks = " ".join(f"{h:.2f}" for h in r["history"][:: max(1, len(r["history"]) // 10)])
        print(
            f"seed {seed}: {r['ratio']:.3f} (best {r['best']:.3f}, {r['actions']} actions, "
            f"heading {r['heading_deg']:.1f} deg, {r['wall_s']:.1f} s) | {marks}",
            flush=True,
        )
        if args.show_gait:
            print(r["gait"])
    passed = sum(r >= 0.95 for r in ratios)
    print(f"{' '.join(args.sets)}: mean {np.mean(ratios):.3f}, >= 0.95: {passed}/{len(ratios)}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
