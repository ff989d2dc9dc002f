"""Trial-and-error adaptation after a change of body, from the intact body's repertoire.

Usage: .venv/bin/python experiments/adaptation/adaptation_table.py --repertoires DIR
           [--seeds 0 1 2] [--changes NEW ...] [--trials 20] [--length-scale L]
           [--oracle] [--warm [--config FILE.yaml] [--workers 1]] [--out runs/adaptation]

For each change (a shipped formation and its changed version, ``CHANGES``) and seed, the
repertoire ``DIR/OLD-seedS`` (made with ``qdsega repertoire``) is adapted to the changed body
(:func:`qdsega.adaptation.adapt.adapt`, into ``OUT/NEW-seedS``), and the table is printed and
written to ``OUT/table.md``: the trials used, the exact distance found, the adaptation's wall
time, and the fresh QDSEGA run's result F and the generations to 0.9 F of a run warm-started
from the old policy for that change and seed (``YARDSTICK``). ``--oracle`` also plays every
mapped gait of the repertoire on the changed body: the best the repertoire holds for it, which
no trial budget can beat. ``--warm`` trains the changed body warm-started from the gait found
(``qdsega train NEW --warm-start OUT/NEW-seedS``, memo mode, the body's own preset, the
seed; into ``OUT/NEW-seedS-warm``, resumed where it stopped) and counts its generations to
0.9 F. A second table takes the median over the seeds of each change.
"""

from __future__ import annotations

import argparse
import math
import statistics
import time
from pathlib import Path
from typing import Any

from qdsega.adaptation.adapt import MappedRepertoire, adapt
from qdsega.adaptation.trial_model import LENGTH_SCALE
from qdsega.agent.policy import SequencePolicy
from qdsega.description import load_formation, resolve_formation
from qdsega.progress import ProgressLine
from qdsega.training.config import resolve_config
from qdsega.training.progress import ProgressDisplay
from qdsega.training.run import train, train_or_resume
from qdsega.training.run_folder import RunFolder

CHANGES = (
    ("hexapod", "hexapod_lost_leg", "a front leg lost"),
    ("legged12", "legged12_locked_leg", "a leg locked"),
    ("snake5", "snake6", "a unit added"),
    ("quadruped", "quadruped_tripod", "a back leg lost (tripod)"),
)
"""(intact formation, changed formation, what changed)."""
YARDSTICK = {
    "hexapod_lost_leg": ((2.188, 29), (1.727, 12), (1.803, 3)),
    "legged12_locked_leg": ((1.904, 13), (2.202, 20), (1.840, 1)),
    "snake6": ((2.231, 26), (2.686, 0), (1.740, 0)),
    "quadruped_tripod": ((0.663, 5), (0.541, 13), (0.532, 6)),
}
"""Per change, per seed 0-2: (the fresh QDSEGA run's F (m), the generations to 0.9 F of a run
warm-started from the old policy), from docs/notes/2026-12-01-reconfiguration.md (its runs are
not on every machine; ``experiments/reconfiguration/reconfiguration_table.py`` makes them
again)."""
AIM_SHARE = 0.8
AIM_TRIALS = 20
AIM_WALL_S = 120.0

COLUMNS = (
    "change",
    "seed",
    "repertoire: cells filled, best on the intact body (m)",
    "trials",
    "found (m)",
    "F (m)",
    "found / F",
    "wall (s)",
    "warm from the old policy: generations to 0.9 F",
    "warm from the gait found: generations (steps) to 0.9 F",
    "best in the repertoire on the changed body (m)",
)


def oracle(mapped: MappedRepertoire) -> float:
    """The farthest any of the repertoire's gaits, mapped, walks on the changed body (m)."""
    from qdsega.locomotion.exact_trials import ExactTrials  # starts PyBullet

    rules = mapped.rules()
    with ExactTrials(formation=mapped.changed, rules=rules, workers=2) as trials:
        played = trials.rollouts(
            [SequencePolicy(commands=g) for g in mapped.gaits], steps=rules.task.trial_steps
        )
    return max(t.distance_m for t in played)


def warm_generations(
    adaptation: Path, changed: Path, seed: int, target_m: float, args: argparse.Namespace
) -> tuple[int | None, int | None]:
    """Train ``changed`` warm-started from ``adaptation``'s gait (memo mode, the body's own
    preset, ``seed``; resumed where it stopped): the generation and simulated steps by which
    it first covered ``target_m`` ((None, None): never)."""
    from qdsega.adaptation.adapt import warm_start_from

    overrides = {"sim": "memo", "seed": seed, "workers": args.workers}
    formation = load_formation(changed)
    config = resolve_config(file=args.config, overrides=overrides, formation=formation)
    run = adaptation.with_name(adaptation.name + "-warm")
    progress = ProgressDisplay()  # minutes per run: its generations and the time left
    if RunFolder(run).started:
        train_or_resume(changed, config, run, progress=progress)
    else:
        warm = warm_start_from(adaptation, formation)
        train(changed, config, run, warm_start=warm, progress=progress)
    return RunFolder(run).reached(target_m)


def row(
    repertoires: Path, out: Path, change: tuple[str, str, str], seed: int, args: argparse.Namespace
) -> dict[str, Any]:
    old, new, what = change
    repertoire = repertoires / f"{old}-seed{seed}"
    changed_file = resolve_formation(new)
    changed = load_formation(changed_file)
    start = time.perf_counter()
    result = adapt(
        repertoire,
        changed,
        out / f"{new}-seed{seed}",
        trials=args.trials,
        length_scale=args.length_scale,
    )
    wall = time.perf_counter() - start  # loading and mapping too, not only the trials
    mapped = MappedRepertoire.of(repertoire, changed)
    built = mapped.record
    fresh_f, warm_from_old = YARDSTICK[new][seed]
    warm_found = None
    if args.warm:
        adaptation = out / f"{new}-seed{seed}"
        warm_found = warm_generations(adaptation, changed_file, seed, 0.9 * fresh_f, args)
    return {
        "change": f"{what} (`{new}`)",
        "seed": seed,
        "repertoire": f"{built['filled']}, {built['best_m']:.3f}",
        "trials": len(result["trials"]),
        "found": result["distance_m"],
        "F": fresh_f,
        "share": result["distance_m"] / fresh_f,
        "wall": wall,
        "warm": warm_from_old,
        "warm_found": warm_found,
        "oracle": oracle(mapped) if args.oracle else None,
    }


def markdown(rows: list[dict[str, Any]]) -> str:
    lines = ["| " + " | ".join(COLUMNS) + " |", "|" + "---|" * len(COLUMNS)]
    for r in rows:
        best = "-" if r["oracle"] is None else f"{r['oracle']:.3f} ({r['oracle'] / r['F']:.2f} F)"
        cells = (
            r["change"], r["seed"], r["repertoire"], r["trials"], f"{r['found']:.3f}",
            f"{r['F']:.3f}", f"{r['share']:.2f}", f"{r['wall']:.1f}", r["warm"],
            _reached(r["warm_found"]),
            best,
        )  # fmt: skip
        lines.append("| " + " | ".join(map(str, cells)) + " |")
    lines += [
        "",
        "| change | seeds | median found / F | median trials | median wall (s) | aim met "
        "| median warm from the old policy: generations | median warm from the gait found: "
        "generations |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for change in dict.fromkeys(r["change"] for r in rows):
        mine = [r for r in rows if r["change"] == change]
        share = statistics.median(r["share"] for r in mine)
        trials = statistics.median(r["trials"] for r in mine)
        wall = statistics.median(r["wall"] for r in mine)
        met = share >= AIM_SHARE and trials <= AIM_TRIALS and wall <= AIM_WALL_S
        seeds = ", ".join(str(r["seed"]) for r in mine)
        old = statistics.median(r["warm"] for r in mine)
        found = [r["warm_found"] for r in mine]
        warm = "-"
        if None not in found:  # never counts as more than any number of generations
            middle = statistics.median_low(math.inf if g is None else g for g, _ in found)
            warm = "never" if math.isinf(middle) else f"{middle:g}"
        lines.append(
            f"| {change} | {seeds} | {share:.2f} | {trials:g} | {wall:.1f} | "
            f"{'yes' if met else 'no'} | {old:g} | {warm} |"
        )
    return "\n".join(lines) + "\n"


def _reached(reached: tuple[int | None, int | None] | None) -> str:
    """A warm run's generations (simulated steps) to 0.9 F, never, or - (not trained)."""
    if reached is None:
        return "-"
    generations, steps = reached
    return "never" if generations is None else f"{generations} ({steps:,})"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--repertoires", type=Path, required=True, metavar="DIR")
    parser.add_argument("--seeds", type=int, nargs="+", default=[0, 1, 2], choices=(0, 1, 2))
    parser.add_argument("--changes", nargs="+", metavar="NEW", choices=[c[1] for c in CHANGES])
    parser.add_argument("--trials", type=int, default=AIM_TRIALS)
    parser.add_argument("--length-scale", type=float, default=LENGTH_SCALE)
    parser.add_argument("--oracle", action="store_true", help="also play every mapped gait")
    parser.add_argument("--warm", action="store_true", help="also train from the gait found")
    parser.add_argument(
        "--config", type=Path, metavar="FILE.yaml", help="settings over each warm run's preset"
    )
    parser.add_argument("--workers", type=int, default=1, help="processes of each warm run")
    parser.add_argument("--out", type=Path, default=Path("runs/adaptation"))
    args = parser.parse_args()
    changes = [c for c in CHANGES if args.changes is None or c[1] in args.changes]
    todo = []
    for change in changes:
        for seed in args.seeds:
            if (args.repertoires / f"{change[0]}-seed{seed}").is_dir():
                todo.append((change, seed))
            else:
                print(f"skipped {change[1]} seed {seed}: no {change[0]}-seed{seed} repertoire")
    rows = []
    line = ProgressLine("adaptations", len(todo))
    for change, seed in todo:
        rows.append(row(args.repertoires, args.out, change, seed, args))
        line.update(len(rows), f"{change[1]} seed {seed}")
    line.close()
    table = markdown(rows)
    args.out.mkdir(parents=True, exist_ok=True)
    (args.out / "table.md").write_text(table, encoding="utf-8")
    print(table, end="")


if __name__ == "__main__":
    main()
