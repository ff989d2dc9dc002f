"""``BENCHMARKS.md`` and its figures, from the benchmark's curves.

Every number is read off the curves (:class:`qdsega.bench.curve.Curve`) as a fraction of the
task's yardstick: the mean and the spread (min to max) over seeds at fixed budgets and at the
end of each run, the steps and wall time to reach 0.9 of the yardstick, and one learning-curve
figure per task (fraction against steps, log scale, mean line and min-max band).
"""

from __future__ import annotations

import datetime
import os
import platform
import subprocess
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

from qdsega.bench.curve import Curve
from qdsega.bench.methods import ABLATIONS
from qdsega.bench.runs import BenchRun
from qdsega.bench.tasks import BenchTask
from qdsega.locomotion import CONTROLS_PER_POSTURE

REACH = 0.9
"""The fraction of the yardstick whose cost the report gives (-)."""
SPENT = 0.95
"""The fraction of a budget a run must have spent to count as having reached it (-)."""


@dataclass(frozen=True)
class Provenance:
    """Where and how the numbers were made.

    Attributes:
        machine: a line on the machine (processor, cores).
        date: the date of the run (UTC).
        commit: the commit of the code, with ``+ changes`` when the work tree differed.
        command: the command that produced it.
    """

    machine: str
    date: str
    commit: str
    command: str

    def line(self) -> str:
        return f"{self.machine}; {self.date}; commit {self.commit}; `{self.command}`"


def write_report(
    *,
    tasks: Sequence[BenchTask],
    curves: dict[BenchRun, Curve],
    yardsticks: dict[str, tuple[str, float]],
    throughput: Sequence[tuple[str, str, float]],
    errors: Sequence[str],
    provenance: Provenance,
    out: Path,
) -> Path:
    """Write ``out/BENCHMARKS.md`` and ``out/figures/TASK.png``; return the Markdown file. A task
    without a yardstick (none of its runs finished) gets a line saying so."""
    figures = out / "figures"
    figures.mkdir(parents=True, exist_ok=True)
    lines = [
        "# Benchmarks: QDSEGA against the learners a user would pick instead",
        "",
        f"Produced by `{provenance.command}` ({provenance.machine}; {provenance.date}; "
        f"commit {provenance.commit}). Every figure and table below is read off the runs' "
        "learning curves in `results/`; nothing is typed in by hand.",
        "",
        "A method's score after a budget is the exact distance toward the light of its answer "
        "at that point (QDSEGA and the stable-baselines3 learners: the greedy policy; the "
        "sequence methods: the best posture sequence that completed a trial), as a fraction of "
        "the task's yardstick. Steps are upper-agent steps (postures commanded) spent in the "
        "task's world; for ppo-joint and sac-joint, which set joint targets "
        f"{CONTROLS_PER_POSTURE} times per posture step, their env steps / "
        f"{CONTROLS_PER_POSTURE}: the same physics time.",
        "",
    ]
    for task in tasks:
        if task.name not in yardsticks:
            lines += [f"## {task.name}", "", "No run of this task has finished yet.", ""]
            continue
        name, yardstick = yardsticks[task.name]
        per_method = {
            method: [c for run, c in curves.items() if run.task == task and run.method == method]
            for method in task.methods
        }
        per_method = {m: c for m, c in per_method.items() if c}
        figure = figures / f"{task.name}.png"
        _figure(task, per_method, yardstick, name, provenance, figure)
        lines += _task_section(task, per_method, yardstick, name, figure.relative_to(out))
    lines += _throughput(throughput, provenance)
    if errors:
        lines += ["## Runs that failed", "", *[f"- {e}" for e in errors], ""]
    file = out / "BENCHMARKS.md"
    file.write_text("\n".join(lines), encoding="utf-8")
    return file


def _task_section(
    task: BenchTask,
    per_method: dict[str, list[Curve]],
    yardstick: float,
    yardstick_name: str,
    figure: Path,
) -> list[str]:
    lines = [
        f"## {task.name}",
        "",
        f"{task.formation} in {_place(task)}; "
        f"yardstick: {yardstick_name}, {yardstick:.3f} m; {task.seeds} seeds per method; "
        f"budget {_count(task.budget_steps)} steps. {task.forced}",
        "",
        f"![{task.name} learning curves]({figure.as_posix()})",
        "",
        "Fraction of the yardstick, mean (min-max) over seeds, at fixed budgets (steps); "
        "+ marks a budget some of the method's runs ended before (their protocol or step cap "
        "ended there: their last answer is counted):",
        "",
        "| method | seeds | "
        + " | ".join(_count(b) for b in task.budgets)
        + " | end of run | wall time per run (median, s) |",
        "|---|---|" + "---|" * (len(task.budgets) + 2),
    ]
    for method, curves in per_method.items():
        cells = [f"{len(curves)} of {task.seeds}"]
        for budget in task.budgets:
            mark = " +" if _ended_before(curves, budget) else ""
            values = np.array([c.at(np.array([budget]))[0] for c in curves])
            cells.append(_spread(values, yardstick) + mark)
        ends = np.array([c.distance_m[-1] for c in curves])
        spent = np.mean([c.steps[-1] for c in curves])
        cells.append(f"{_spread(ends, yardstick)} at {_count(spent)}")
        cells.append(f"{np.median([c.wall_s[-1] for c in curves]):.0f}")
        lines.append(f"| {method} | " + " | ".join(cells) + " |")
    hours = sum(c.wall_s[-1] for curves in per_method.values() for c in curves) / 3600
    finished = sum(len(curves) for curves in per_method.values())
    lines += [
        "",
        f"Its {finished} finished runs (of {task.seeds * len(task.methods)}) took "
        f"{hours:.1f} h of one core in all.",
        "",
        f"Cost to reach {REACH} of the yardstick (median over the seeds that reached it):",
        "",
        "| method | seeds that reached it | steps | wall time (s) |",
        "|---|---|---|---|",
    ]
    for method, curves in per_method.items():
        hits = [c.first_reaching(REACH * yardstick) for c in curves]
        reached = [h for h in hits if h is not None]
        if reached:
            steps = _count(np.median([h[0] for h in reached]))
            wall = f"{np.median([h[1] for h in reached]):.3g}"
        else:
            steps = wall = "not reached"
        lines.append(f"| {method} | {len(reached)} of {len(curves)} | {steps} | {wall} |")
    lines += ["", *_headline(task, per_method, yardstick), ""]
    return lines


def _place(task: BenchTask) -> str:
    """Where the task walks, in words: ``the MSM``, or ``the PyBullet world stairs (ten 4 cm
    steps, 0.3 m deep)``."""
    if task.sim == "msm":
        return "the MSM"
    world = task.load_world()
    return f"the PyBullet world {world.name} ({world.description})"


def _headline(task: BenchTask, per_method: dict[str, list[Curve]], yardstick: float) -> list[str]:
    """Where QDSEGA is ahead or behind the best other method, budget by budget."""
    if "qdsega" not in per_method:
        return []
    lines = [
        "Where QDSEGA stands (mean fraction against the best method other than QDSEGA and its "
        "ablations, among those whose runs all reached the budget; QDSEGA counted also where "
        "its runs ended before):",
        "",
    ]
    for budget in task.budgets:
        means = {
            method: np.mean([c.at(np.array([budget]))[0] for c in curves]) / yardstick
            for method, curves in per_method.items()
            if method == "qdsega" or (method not in ABLATIONS and not _ended_before(curves, budget))
        }
        if "qdsega" not in means or len(means) < 2:
            continue
        ours = means.pop("qdsega")
        rival = max(means, key=lambda m: means[m])
        theirs = means[rival]
        if theirs > 0 and ours > 0:
            verdict = f"{'ahead' if ours >= theirs else 'behind'}, ratio {ours / theirs:.2f}"
        else:
            verdict = "ahead" if ours > theirs else "behind" if ours < theirs else "level"
        lines.append(
            f"- at {_count(budget)} steps: QDSEGA {ours:.2f}, best other {rival} {theirs:.2f} "
            f"({verdict})"
        )
    return lines


def _ended_before(curves: Sequence[Curve], budget: int) -> bool:
    """Whether a run ended before ``budget`` steps; one that spent :data:`SPENT` of it counts
    as having reached it (CMA-ES spends its budget in whole trials, and failed ones end early)."""
    return min(c.steps[-1] for c in curves) < SPENT * budget


def _count(steps: float) -> str:
    """Steps as ``3,000`` below 1e5, else as ``1.2e6``."""
    if steps < 1e5:
        return f"{steps:,.0f}"
    mantissa, exponent = f"{steps:.1e}".split("e")
    return f"{mantissa.removesuffix('.0')}e{int(exponent)}"


def _spread(distances: np.ndarray, yardstick: float) -> str:
    f = distances / yardstick
    return f"{f.mean():.2f} ({f.min():.2f}-{f.max():.2f})"


def _figure(
    task: BenchTask,
    per_method: dict[str, list[Curve]],
    yardstick: float,
    yardstick_name: str,
    provenance: Provenance,
    file: Path,
) -> None:
    fig, ax = plt.subplots(figsize=(8, 5))
    first = max(1, min(int(c.steps[0]) for cs in per_method.values() for c in cs if len(c.steps)))
    for method, curves in per_method.items():
        last = min(int(c.steps[-1]) for c in curves)
        if last < first:
            continue
        grid = np.unique(np.geomspace(first, last, 300).astype(np.int64))
        values = np.array([c.at(grid) for c in curves]) / yardstick
        (line,) = ax.plot(grid, values.mean(axis=0), label=f"{method} ({len(curves)} seeds)")
        ax.fill_between(grid, values.min(axis=0), values.max(axis=0), alpha=0.15, lw=0,
                        color=line.get_color())  # fmt: skip
    ax.axhline(REACH, color="grey", lw=0.8, ls=":")
    ax.set_xscale("log")
    ax.set_xlabel("upper-agent steps spent in the world")
    ax.set_ylabel(f"fraction of {yardstick_name} ({yardstick:.2f} m)")
    ax.set_title(f"{task.name}: mean and min-max over seeds")
    ax.legend(fontsize=8, loc="upper left")
    ax.grid(True, which="both", alpha=0.3)
    fig.text(0.01, 0.005, provenance.line(), fontsize=6, color="grey")
    fig.tight_layout(rect=(0, 0.03, 1, 1))
    fig.savefig(file, dpi=110)
    plt.close(fig)


def _throughput(rows: Sequence[tuple[str, str, float]], provenance: Provenance) -> list[str]:
    lines = [
        "## Throughput on this machine",
        "",
        f"{provenance.line()}. One process; a reference gait (`qdsega.bench.throughput`).",
        "",
        "| figure | formation | value |",
        "|---|---|---|",
    ]
    lines += [f"| {what} | {formation} | {value:,.0f} |" for what, formation, value in rows]
    return [*lines, ""]


def provenance(command: str) -> Provenance:
    """This machine, today, the checkout's commit, and ``command``."""
    source = Path(__file__).resolve().parent
    commit = _git(source, "rev-parse", "--short", "HEAD") or "unknown (not a git checkout)"
    if _git(source, "status", "--porcelain", "--untracked-files=no"):
        commit += " + changes"
    machine = f"{platform.machine()} {platform.processor() or platform.system()}".strip()
    return Provenance(
        machine=f"{machine}, {os.cpu_count()} cores, Python {platform.python_version()}",
        date=datetime.datetime.now(datetime.UTC).strftime("%Y-%m-%d %H:%M UTC"),
        commit=commit,
        command=command,
    )


def _git(folder: Path, *args: str) -> str:
    try:
        done = subprocess.run(
            ["git", *args], cwd=folder, capture_output=True, text=True, check=True, timeout=30
        )
    except (OSError, subprocess.SubprocessError):
        return ""
    return done.stdout.strip()
