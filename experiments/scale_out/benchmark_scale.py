"""Benchmark: what scale-out costs and buys, on this machine.

Usage: .venv/bin/python experiments/scale_out/benchmark_scale.py [--transitions 60]
           [--sweep-seeds 4] [--protocols] [--machines 8 64]

Prints:
- memo transitions measured per second by one worker, for snake5 and legged12 (random
  posture pairs, grouped by start posture as memo mode groups them);
- the same small sweep (snake5, memo mode, tiny budgets, ``--sweep-seeds`` seeds) on local
  processes (``--jobs 2``) and on ``--ray local``: wall times, and whether the tables agree;
- Ray's overhead: the wall time of a round trip of trivial work through Ray actors (per call)
  and of starting a local Ray instance;
- with ``--protocols``, the wall times of the snake protocol (snake5, memo, paper-snake) and of
  the MSM protocol (legged12, paper-legged), each one run;
- a projection, on paper, of the full legged protocol in memo mode (``PAPER_TRANSITIONS``
  transitions of legged12) on ``--machines`` machines of two workers each, from the measured
  per-worker rate plus Ray's per-call overhead (one call a transition, an upper bound: memo
  mode sends a start posture with all its targets), with the learning itself (the MSM protocol's
  wall time, which does not spread) added once.
"""

from __future__ import annotations

import argparse
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from qdsega.description import load_formation, resolve_formation
from qdsega.locomotion.lower_agent import LowerAgentConfig
from qdsega.locomotion.memo import MeasuredTransitions
from qdsega.sweep import read_grid, run_sweep
from qdsega.training.config import resolve_config
from qdsega.training.run import train

PAPER_TRANSITIONS = 283_000
"""Distinct legged12 transitions the paper's legged protocol needs (measured once by counting a
paper-legged run's table in the MSM's posture space; issue 11)."""
MSM_PROTOCOL_S = 10.0
"""The MSM protocol's wall time per seed on one core (``experiments/msm/benchmark_msm.py``:
9.7-9.8 s, 2026-12-03), used in the projection unless ``--protocols`` measures it."""
SWEEP_GRID = """\
formations: [snake5]
seeds: {seeds}
sim: memo
configs:
  tiny: {{agent: {{genetic: {{generations: 2, population: 6}}, learning: {{trials: 50}}}},
         task: {{trial_steps: 6}}, workers: 1}}
reference_trials: 0
"""


def memo_rate(name: str, transitions: int) -> float:
    """Transitions per second one worker measures for formation ``name``: 4 random start
    postures, each to ``transitions // 4`` random targets."""
    formation = load_formation(resolve_formation(Path(name)))
    counts = np.array([len(j.levels_rad) for j in formation.joints])
    rng = np.random.default_rng(0)
    sources = 4
    postures = rng.integers(0, counts, size=(1 + sources + transitions // sources, len(counts)))
    memo = MeasuredTransitions(formation=formation, lower_agent=LowerAgentConfig(), workers=1)
    try:
        memo.transitions(postures[:1], postures[:1])  # builds the world: not part of the rate
        before = memo.measured
        start = time.perf_counter()
        memo.transitions(postures[1 : 1 + sources], postures[1 + sources :])
        return (memo.measured - before) / (time.perf_counter() - start)
    finally:
        memo.close()


def sweep_times(seeds: int) -> tuple[float, float, bool]:
    """Wall times (s) of the same sweep on local processes and on Ray, and whether their
    tables agree."""
    with tempfile.TemporaryDirectory() as scratch:
        grid = Path(scratch) / "grid.yaml"
        grid.write_text(SWEEP_GRID.format(seeds=list(range(seeds))))
        times, tables = [], []
        for label, options in (("local", {"jobs": 2}), ("ray", {"ray": "local"})):
            out = Path(scratch) / label
            start = time.perf_counter()
            rows = run_sweep(read_grid(grid, out), out, **options)
            times.append(time.perf_counter() - start)
            tables.append([{k: v for k, v in r.items() if k != "run"} for r in rows])
        return times[0], times[1], tables[0] == tables[1]


def ray_overhead(calls: int = 200) -> tuple[float, float]:
    """(starting a local Ray instance (s), one trivial call through a Ray actor pool (s))."""
    from qdsega.workers.pool import worker_pool

    start = time.perf_counter()
    pool = worker_pool(2, _nothing, (), ray="local")
    list(pool.map(abs, [0]))
    started = time.perf_counter() - start
    start = time.perf_counter()
    list(pool.map(abs, range(calls)))
    per_call = (time.perf_counter() - start) / calls
    pool.shutdown()
    return started, per_call


def _nothing() -> None:
    """A worker initializer that sets nothing up."""


def protocol_times() -> tuple[float, float]:
    """Wall times (s) of the snake protocol and of the MSM protocol, one run each."""

    with tempfile.TemporaryDirectory() as scratch:
        walls = []
        for name, overrides in (
            ("snake5", {"preset": "paper-snake", "sim": "memo", "workers": 2}),
            ("legged12", {"preset": "paper-legged", "sim": "msm"}),
        ):
            config = resolve_config(overrides=overrides)
            start = time.perf_counter()
            train(resolve_formation(Path(name)), config, Path(scratch) / name)
            walls.append(time.perf_counter() - start)
        return walls[0], walls[1]


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--transitions", type=int, default=60)
    parser.add_argument("--sweep-seeds", type=int, default=4)
    parser.add_argument("--protocols", action="store_true")
    parser.add_argument("--machines", type=int, nargs="+", default=[8, 64])
    args = parser.parse_args()
    if args.transitions < 4 or args.sweep_seeds < 1:
        parser.error("--transitions must be at least 4 and --sweep-seeds at least 1")
    rates = {name: memo_rate(name, args.transitions) for name in ("snake5", "legged12")}
    for name, rate in rates.items():
        print(f"memo transitions per second, one worker, {name}: {rate:.1f}", flush=True)
    started, per_call = ray_overhead()  # first: the Ray instance starts here
    print(f"Ray: local instance and 2 actors started in {started:.1f} s; {per_call * 1e3:.2f} ms "
          "per call through the actor pool", flush=True)  # fmt: skip
    local, ray, same = sweep_times(args.sweep_seeds)
    print(
        f"sweep of {args.sweep_seeds} snake5 memo runs: local processes (--jobs 2) {local:.1f} s, "
        f"--ray local {ray:.1f} s ({ray / local:.2f}x); same table: {same}",
        flush=True,
    )
    learning = MSM_PROTOCOL_S
    if args.protocols:
        snake, learning = protocol_times()
        print(f"snake protocol (snake5, memo, paper-snake, 2 workers): {snake:.1f} s")
        print(f"MSM protocol (legged12, paper-legged), one seed: {learning:.1f} s")
    rate = rates["legged12"]
    per_transition = 1.0 / rate + per_call  # at most one call a transition: an upper bound
    print(f"full legged protocol in memo mode ({PAPER_TRANSITIONS:,} transitions), projected:")
    for machines in [1, *args.machines]:
        workers = 2 * machines
        measuring = PAPER_TRANSITIONS * per_transition / workers
        print(
            f"  {machines:3d} machines x 2 workers: {(measuring + learning + started) / 60:7.1f} "
            f"min (measuring {measuring / 60:.1f} min, learning {learning / 60:.1f} min, Ray start "
            f"{started:.0f} s)"
        )
    return 0


if __name__ == "__main__":
    sys.exit(main())
