"""Relearning after a change of body: the old policy on it, a fresh run, a warm-started run.

Usage: .venv/bin/python tools/reconfiguration_table.py [--seeds 0 1 2] [--grid runs/grid]
                                                        [--out runs/reconfiguration] [--workers 2]
                                                        [--changes NEW ...]

For each change (a shipped formation and its changed version, ``CHANGES``) and seed: the old
formation's run ``GRID/OLD-seedS`` (as ``tools/fidelity_grid.py`` trains it: memo mode, the
README's preset; kept if it is there), ``qdsega evaluate`` of it on the changed body, a fresh
run of the changed body ``OUT/fresh/NEW-seedS`` and one warm-started from the old run
``OUT/warm/NEW-seedS`` (same preset and seed). A finished run is kept, an unfinished one
resumed. Then the table, printed and written to ``OUT/table.md``: per seed, the old policy's
exact distance on the changed body, the fresh run's result F (its farthest exact generation),
and the generations (and simulated steps: memo transitions measured and exact trials'
commands) each run needs until its greedy policy covers 0.9 F with exact physics: 0 for a
warm run whose handed-on path already covers it when verified, before it learns at all.
"""

from __future__ import annotations

import argparse
import csv
import json
import statistics
from dataclasses import dataclass
from pathlib import Path

from fidelity_grid import qdsega, train
from formation_table import markdown

CHANGES = (
    ("hexapod", "hexapod_lost_leg", "a front leg lost"),
    ("legged12", "legged12_locked_leg", "a leg locked"),
    ("snake5", "snake6", "a unit added"),
    ("quadruped", "quadruped_tripod", "a back leg lost (tripod)"),
)
"""(old formation, changed formation, what changed)."""

COLUMNS = (
    "change",
    "seed",
    "old policy on the new body (m)",
    "fresh final F (m)",
    "fresh: generations (steps) to 0.9 F",
    "warm: handed-on path verified (m)",
    "warm: first generation (m)",
    "warm: generations (steps) to 0.9 F",
    "warm / fresh generations",
    "warm final (m)",
)
AGGREGATE_COLUMNS = (
    "change",
    "seeds",
    "old policy on the new body (m)",
    "fresh final F (m)",
    "fresh generations to 0.9 F",
    "warm generations to 0.9 F",
    "warm / fresh generations",
    "warm / fresh simulated steps",
    "aim: warm <= 20 % of fresh",
)


@dataclass(frozen=True)
class Change:
    """One seed of one change: the old policy on the new body (m), the fresh run's result
    F (m, its farthest exact generation), the (generation, simulated steps) at which the
    fresh and the warm run first reach 0.9 F, and warm over fresh generations."""

    moved_m: float
    fresh_m: float
    fresh: tuple[int | None, int | None]
    warm: tuple[int | None, int | None]
    share: float | None


def reach(run: Path, target_m: float) -> tuple[int | None, int | None]:
    """The first generation whose greedy policy covers ``target_m`` with exact physics, and
    the run's simulated steps by its end; generation 0 (and the commands of that one trial)
    for a warm run whose handed-on path, verified before generation 1 (``handed_on_m`` in
    ``warm_start.json``), already covers it; (None, None) when no generation does."""
    warm = run / "warm_start.json"
    if warm.is_file():
        record = json.loads(warm.read_text(encoding="utf-8"))
        if record.get("handed_on_m", -1.0) >= target_m:
            return 0, int(record["handed_on_steps"])
    with (run / "metrics.csv").open(encoding="utf-8") as stream:
        for row in csv.DictReader(stream):
            if float(row["greedy_exact_m"]) >= target_m:
                return int(row["generation"]), int(row["sim_steps"])
    return None, None


def handed_on(run: Path) -> str:
    """How far a warm run's handed-on path walked when verified (m), or why it is unknown."""
    record = json.loads((run / "warm_start.json").read_text(encoding="utf-8"))
    if "handed_on_m" not in record:
        return "not recorded"
    return f"{record['handed_on_m']:.3f}"


def first_exact(run: Path) -> float:
    with (run / "metrics.csv").open(encoding="utf-8") as stream:
        return float(next(csv.DictReader(stream))["greedy_exact_m"])


def _count(generations: int | None, steps: int | None) -> str:
    return "not reached" if generations is None else f"{generations} ({steps:,})"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", nargs="+", type=int, default=[0, 1, 2])
    parser.add_argument("--grid", type=Path, default=Path("runs/grid"))
    parser.add_argument("--out", type=Path, default=Path("runs/reconfiguration"))
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument(
        "--changes",
        nargs="+",
        choices=[c[1] for c in CHANGES],
        default=[c[1] for c in CHANGES],
        help="changed formations",
    )
    args = parser.parse_args()
    rows, aggregates = [], []
    for old, new, what in (c for c in CHANGES if c[1] in args.changes):
        found = []
        for seed in args.seeds:
            base = args.grid / f"{old}-seed{seed}"
            fresh = args.out / "fresh" / f"{new}-seed{seed}"
            warm = args.out / "warm" / f"{new}-seed{seed}"
            train(old, seed, base, args.workers)
            transfer = base / f"evaluation-on-{new}.json"
            if not transfer.is_file():
                qdsega("evaluate", base, "--formation", new)
            train(new, seed, fresh, args.workers)
            train(new, seed, warm, args.workers, "--warm-start", base)
            moved = json.loads(transfer.read_text(encoding="utf-8"))["distance_m"]
            final = json.loads((fresh / "summary.json").read_text(encoding="utf-8"))
            target = 0.9 * final["distance_m"]
            fresh_reach, warm_reach = reach(fresh, target), reach(warm, target)
            share = (
                warm_reach[0] / fresh_reach[0]
                if warm_reach[0] is not None and fresh_reach[0] is not None
                else None
            )
            warm_final = json.loads((warm / "summary.json").read_text(encoding="utf-8"))
            found.append(Change(moved, final["distance_m"], fresh_reach, warm_reach, share))
            rows.append([
                what, str(seed), f"{moved:.3f}", f"{final['distance_m']:.3f}",
                _count(*fresh_reach), handed_on(warm), f"{first_exact(warm):.3f}",
                _count(*warm_reach),
                "" if share is None else f"{share:.2f}", f"{warm_final['distance_m']:.3f}",
            ])  # fmt: skip
        aggregates.append(_aggregate(what, found))
    text = markdown(COLUMNS, rows) + "\n\n" + markdown(AGGREGATE_COLUMNS, aggregates)
    args.out.mkdir(parents=True, exist_ok=True)
    (args.out / "table.md").write_text(text + "\n", encoding="utf-8")
    print(text)


def _aggregate(what: str, found: list[Change]) -> list[str]:
    """Medians over the seeds of one change. A warm run that never reaches 0.9 F leaves the
    share undefined and the aim missed."""
    fresh = [c.fresh[0] for c in found if c.fresh[0] is not None]
    warm = [c.warm[0] for c in found if c.warm[0] is not None]
    shares = [c.share for c in found if c.share is not None]
    steps = [c.warm[1] / c.fresh[1] for c in found if c.warm[1] and c.fresh[1]]
    median_share = statistics.median(shares) if len(shares) == len(found) else None
    return [
        what,
        str(len(found)),
        f"{statistics.median(c.moved_m for c in found):.3f}",
        f"{statistics.median(c.fresh_m for c in found):.3f}",
        f"{statistics.median(fresh):g}" if fresh else "not reached",
        f"{statistics.median(warm):g}" if len(warm) == len(found) else "not reached by every seed",
        "" if median_share is None else f"{median_share:.2f}",
        f"{statistics.median(steps):.2f}" if steps else "",
        "MISSED" if median_share is None or median_share > 0.2 else "met",
    ]


if __name__ == "__main__":
    main()
