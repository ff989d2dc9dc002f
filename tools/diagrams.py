"""The docs' pictures, each drawn by one subcommand into docs/figures/ (or ``--out``).

Usage: .venv/bin/python tools/diagrams.py loop|memo|archive REPERTOIRE|adaptation ADAPT
[--fresh RUN]|report RUN [--window WxH] [--out FILE.png]

* ``loop``: QDSEGA's generation loop (Fig. 7 of the paper) as ``qdsega.agent`` runs it.
* ``memo``: memo mode's pipeline, measured table to grounded table, as ``qdsega train --sim
  memo`` runs it.
* ``archive REPERTOIRE``: a ``qdsega repertoire`` folder's archive as heat maps of its
  descriptor, two axes at a time.
* ``adaptation ADAPT``: a ``qdsega adapt`` folder's curve (``--fresh RUN``: with a fresh run's
  result F), drawn as ``qdsega adapt`` draws it.
* ``report RUN``: a screenshot of ``RUN/report.html`` (``qdsega report``) in headless Chromium,
  the top of the page in a window of ``--window`` pixels.

Bad input is one line on stderr and exit status 2.
"""

from __future__ import annotations

import argparse
import json
import shutil
import subprocess
import sys
import tempfile
import textwrap
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
from matplotlib.patches import FancyArrowPatch, FancyBboxPatch
from matplotlib.path import Path as MplPath
from PIL import Image

from qdsega.adaptation.folders import AdaptationFolder
from qdsega.analysis.adaptation_plots import adaptation_curve, archive_heat_map
from qdsega.analysis.pictures import figure_pixels, save_png
from qdsega.errors import QdsegaError, RunFolderError
from qdsega.training.run_folder import RunFolder

FIGURES = Path(__file__).resolve().parents[1] / "docs" / "figures"
"""Where each picture goes unless ``--out`` says otherwise."""
NAMES = {
    "loop": "qdsega_loop.png",
    "memo": "memo_pipeline.png",
    "archive": "repertoire_archive.png",
    "adaptation": "adaptation_curve.png",
    "report": "report_screenshot.png",
}
"""Each subcommand's file in ``FIGURES``."""
CHROMIUM = ("chromium", "chromium-browser", "google-chrome")
"""The browsers ``report`` looks for on the PATH, in order."""
WINDOW = (1200, 900)
"""The screenshot's window (px): the top of the page as a user first sees it."""
DPI = 100
"""The diagrams' resolution (dots per inch): a figure of 12 x 6.4 inches is 1200 x 640 px."""
COLOURS = 64
"""A diagram's palette: a few fills and the text's anti-aliasing; a third of the full PNG's size."""
CHARS_PER_UNIT = 14.3
"""Characters of 8.5 pt text that fit in one unit of a box's width, its margins left."""
GREEN, BLUE, ORANGE, GREY = "#e3f1e0", "#e1ebf7", "#fbe9d6", "#eeeeee"
"""The boxes' fills: the GA's population, learning, rating and checking, the result."""


@dataclass(frozen=True, kw_only=True)
class Box:
    """A step of a diagram: a bold title over a paragraph, centred at (x, y) on a 12 x 6.4
    canvas (1 = 100 px).

    Attributes:
        x, y: the centre.
        title: one line, bold.
        text: the paragraph, wrapped to the box's width.
        colour: the fill.
        width, height: the box's size.
        source: the modules that do the step, in grey at the bottom.
    """

    x: float
    y: float
    title: str
    text: str
    colour: str
    width: float = 3.0
    height: float = 2.0
    source: str = ""

    @property
    def left(self) -> tuple[float, float]:
        return (self.x - self.width / 2, self.y)

    @property
    def right(self) -> tuple[float, float]:
        return (self.x + self.width / 2, self.y)

    @property
    def top(self) -> tuple[float, float]:
        return (self.x, self.y + self.height / 2)

    @property
    def bottom(self) -> tuple[float, float]:
        return (self.x, self.y - self.height / 2)


def _canvas(title: str) -> tuple[plt.Figure, plt.Axes]:
    """An empty 12 x 6.4 canvas with ``title`` on top."""
    fig = plt.figure(figsize=(12, 6.4))
    ax = fig.add_axes((0, 0, 1, 1))
    ax.set_xlim(0, 12)
    ax.set_ylim(0, 6.4)
    ax.axis("off")
    ax.text(0.15, 6.25, title, fontsize=13, fontweight="bold", ha="left", va="top")
    return fig, ax


def _draw_box(ax: plt.Axes, box: Box) -> None:
    """``box`` with its title, wrapped body and source."""
    ax.add_patch(
        FancyBboxPatch(
            (box.x - box.width / 2, box.y - box.height / 2),
            box.width,
            box.height,
            boxstyle="round,pad=0.02,rounding_size=0.12",
            facecolor=box.colour,
            edgecolor="#444444",
            linewidth=1.2,
        )
    )
    chars = int(box.width * CHARS_PER_UNIT)
    body = textwrap.fill(box.text, chars, break_on_hyphens=False)
    top = box.y + box.height / 2 - 0.12
    ax.text(box.x, top, box.title, ha="center", va="top", fontsize=10.5, fontweight="bold")
    ax.text(box.x - box.width / 2 + 0.12, top - 0.3, body, ha="left", va="top", fontsize=8.5)
    if box.source:
        bottom = box.y - box.height / 2 + 0.08
        ax.text(box.x, bottom, box.source, ha="center", va="bottom", fontsize=7.5, color="#555555")


def _arrow(
    ax: plt.Axes,
    points: Sequence[tuple[float, float]],
    label: str = "",
    *,
    at: tuple[float, float] | None = None,
    dashed: bool = False,
) -> None:
    """An arrow along the polyline ``points``, its ``label`` centred at ``at``; by default
    above a horizontal first segment, or on the middle of another."""
    codes = [MplPath.MOVETO] + [MplPath.LINETO] * (len(points) - 1)
    ax.add_patch(
        FancyArrowPatch(
            path=MplPath(points, codes),
            arrowstyle="-|>",
            mutation_scale=16,
            linewidth=1.6,
            linestyle="--" if dashed else "-",
            color="#333333",
        )
    )
    if not label:
        return
    (x0, y0), (x1, y1) = points[0], points[1]
    if at is None and y0 == y1:  # a horizontal arrow: the label above it
        ax.text((x0 + x1) / 2, y0 + 0.06, label, ha="center", va="bottom", fontsize=8.5,
                style="italic")  # fmt: skip
        return
    x, y = at or ((x0 + x1) / 2, (y0 + y1) / 2)
    ax.text(
        x,
        y,
        label,
        ha="center",
        va="center",
        fontsize=8.5,
        style="italic",
        bbox={"boxstyle": "round,pad=0.2", "facecolor": "white", "edgecolor": "none"},
    )


def _save(fig: plt.Figure, out: Path) -> Path:
    """Write ``fig`` to ``out`` as a PNG of at most ``COLOURS`` colours, and close it."""
    pixels = figure_pixels(fig, dpi=DPI)
    return save_png(pixels, out, colours=COLOURS, method=Image.Quantize.MEDIANCUT)


def draw_loop(out: Path) -> Path:
    """QDSEGA's loop: population, actions, Q-learning, fitness, selection and reproduction,
    with the paper's equation numbers and the elitism the run adds."""
    fig, ax = _canvas("QDSEGA: one generation (the paper's Fig. 7, as qdsega.agent runs it)")
    population = Box(
        x=2.0, y=4.3, title="1. Population (GA)",
        text="N genes, one character per actuated joint: its level index; the phenotype is a "
            "posture. N = 200 (paper-legged), 40 (memo-legged), 30 (paper-snake). The first "
            "population is drawn at random.",
        colour=GREEN, source="agent/genetic.py",
    )  # fmt: skip
    actions = Box(
        x=6.0, y=4.3, title="2. Action set and Q-table",
        text="Genes with the same phenotype are one action: the distinct postures (Fig. 8). "
            "States: interior (the start posture and each action's) x exterior (the light's "
            "bearing, 4 bins). Q starts from the last generation's where state and action "
            "persist (carry_q).",
        colour=BLUE, source="agent/space.py, learner.py",
    )  # fmt: skip
    learning = Box(
        x=10.0, y=4.3, title="3. Q-learning in the world",
        text="Trials of 30 commands from the start posture, on a table, in the MSM or in "
            "PyBullet; 10000 a generation (1000 for snakes). Boltzmann selection at T of "
            "eq. (18); reward eq. (17); update eq. (1), alpha 0.5, gamma 0.9. A failed "
            "command: the penalty, and the trial ends.",
        colour=BLUE, source="agent/qlearning.py, world_loop.py",
    )  # fmt: skip
    fitness = Box(
        x=10.0, y=1.4, title="4. Fitness of each action",
        text="Q regulated per state to [0, 1] (eqs. 2-3); fit_Q: the top-j means over all states "
            "(eq. 4, w_1 = 0, w_Ns = 1); fit_u: its share of the uses (eq. 5); "
            "fit = fit_Q + k_f fit_u (eq. 6), k_f = 1000.",
        colour=ORANGE, source="agent/fitness.py",
    )  # fmt: skip
    reproduce = Box(
        x=6.0, y=1.4, title="5. Selection and reproduction",
        text="Roulette wheel, one slot per action as large as its fitness, shared by its genes; "
            "crossover in pairs (uniform 0.2, or one-point 0.5 for snakes); mutation per "
            "character to another level (0.001, or 0.02 for snakes).",
        colour=ORANGE, source="agent/genetic.py",
    )  # fmt: skip
    elite = Box(
        x=2.0, y=1.4, title="The best exact trial",
        text="Each generation's greedy policy with exact physics (replayed where it learnt on a "
            "table): the farthest is the run's result. The farthest exact trial's postures go "
            "back into a population that lost them (elitism, at most N/2).",
        colour=GREY, source="learner.py: verify, genetic.py: with_elite",
    )  # fmt: skip
    for box in (population, actions, learning, fitness, reproduce, elite):
        _draw_box(ax, box)
    _arrow(ax, [population.right, actions.left], "phenotypes")
    _arrow(ax, [actions.right, learning.left], "Q(s, a), eq. (1)")
    _arrow(ax, [learning.bottom, fitness.top], "learnt Q (eqs. 2-4), uses N_u(a) (eq. 5)")
    _arrow(ax, [fitness.left, reproduce.right], "fit(a), eq. (6)")
    _arrow(
        ax,
        [reproduce.top, (reproduce.x, 2.85), (2.6, 2.85), (2.6, population.bottom[1])],
        "next generation", at=(4.3, 2.85),
    )  # fmt: skip
    _arrow(
        ax,
        [learning.right, (11.85, learning.y), (11.85, 0.2), (elite.x, 0.2), elite.bottom],
        "greedy policy", at=(7.0, 0.2), dashed=True,
    )  # fmt: skip
    _arrow(
        ax, [(1.4, elite.top[1]), (1.4, population.bottom[1])], "elite postures",
        at=(1.4, 2.85), dashed=True,
    )  # fmt: skip
    return _save(fig, out)


def draw_memo(out: Path) -> Path:
    """Memo mode's pipeline: moves measured once, the table, learning on it, exact replays,
    and the table grounded in what they observed."""
    fig, ax = _canvas("Memo mode: learn on measured moves, check and correct them in exact physics")
    measure = Box(
        x=2.0, y=4.2, title="1. Measure each move once",
        text="For each posture pair i -> j not yet in the table: settle the robot in i, command "
            "j through the lower agent, keep its move in the body frame (dx, dy, dtheta) and "
            "whether the command failed. Grouped by start posture, spread over --workers "
            "PyBullet processes; on varied ground, the mean over 6 spots (memo_spots).",
        colour=GREEN, height=2.0, source="locomotion/memo.py",
    )  # fmt: skip
    table = Box(
        x=6.0, y=4.2, title="2. The transition table",
        text="The measured moves (transitions.npz). Asked for i -> j, the grounded table answers, "
            "the first it knows: a remembered exact trial's move where the walk follows that "
            "trial; the latest i -> j observed after posture h; the mean observed i -> j; the "
            "measurement less the RMS gap.",
        colour=BLUE, height=2.0, source="agent/grounding.py",
    )  # fmt: skip
    learn = Box(
        x=10.0, y=4.2, title="3. Learn on the table",
        text="One generation of QDSEGA, compiled (numba): every trial of the preset on the "
            "table, then the GA. The greedy policy's walk on the table is its prediction "
            "(greedy_distance_m).",
        colour=BLUE, height=2.0, source="agent/learner.py, qlearning.py",
    )  # fmt: skip
    replay = Box(
        x=10.0, y=1.4, title="4. Replay in exact physics",
        text="Every command simulated, over the workers: exploring trials of the Q-table "
            "(explore_trials 4), one policy learnt on the table's upper bound (optimism), the "
            "greedy policy (greedy_exact_m: the learning curve), then neighbours of the best "
            "exact trial so far (local_search 10).",
        colour=ORANGE, height=2.0, source="agent/verification.py, locomotion/exact_trials.py",
    )  # fmt: skip
    ground = Box(
        x=6.0, y=1.4, title="5. Ground the table",
        text="Every command of every exact trial is observed: its move, keyed on the posture "
            "pair and the posture before (ground_table). The farthest exact trial becomes the "
            "learner's elite (elitism) and the local search's parent.",
        colour=ORANGE, height=2.0, source="training/sims.py: observe, learner.py: verify",
    )  # fmt: skip
    result = Box(
        x=2.0, y=1.4, title="The run's result",
        text="The farthest greedy replay of any generation, with exact physics (distance_m in "
            "summary.json); metrics.csv holds each generation's prediction (3) and exact "
            "replay (4).",
        colour=GREY, height=2.0, source="training/run.py",
    )  # fmt: skip
    for box in (measure, table, learn, replay, ground, result):
        _draw_box(ax, box)
    _arrow(ax, [measure.right, table.left], "moves")
    _arrow(ax, [table.right, learn.left], "answers")
    _arrow(ax, [learn.bottom, replay.top], "policies to play")
    _arrow(ax, [replay.left, ground.right], "their moves")
    _arrow(ax, [ground.top, table.bottom], "corrections")
    _arrow(
        ax,
        [learn.top, (learn.x, 5.7), (measure.x, 5.7), measure.top],
        "next generation: the GA's new postures; only new pairs are measured",
        at=(6.0, 5.7),
    )  # fmt: skip
    _arrow(
        ax, [replay.bottom, (replay.x, 0.2), (result.x, 0.2), result.bottom], "greedy replays",
        at=(4.0, 0.2), dashed=True,
    )  # fmt: skip
    return _save(fig, out)


def draw_archive(repertoire: Path, out: Path) -> Path:
    """The heat maps of ``repertoire``'s archive (a ``qdsega repertoire`` folder).

    Raises:
        RunFolderError: not a repertoire, or an empty one.
    """
    from qdsega.adaptation.repertoire import load_repertoire  # loads PyBullet: only here

    archive, record = load_repertoire(repertoire)
    if not len(archive.filled):
        raise RunFolderError("the archive holds no elite", file=repertoire)
    out.parent.mkdir(parents=True, exist_ok=True)
    return archive_heat_map(archive, record, out)


def draw_adaptation(adaptation: Path, out: Path, *, fresh: Path | None) -> Path:
    """The curve of ``adaptation`` (a ``qdsega adapt`` folder), with the result F of the
    finished run ``fresh`` where given.

    Raises:
        RunFolderError: not an adaptation, a corrupt one, or ``fresh`` not a finished run.
    """
    from qdsega.adaptation.adapt import is_adaptation  # loads PyBullet: only here

    fresh_m = None
    if fresh is not None:
        folder = RunFolder(fresh)
        folder.require_finished()
        fresh_m = float(folder.read_summary()["distance_m"])
    if not is_adaptation(adaptation):
        raise RunFolderError("not an adaptation (no adapt.json)", file=adaptation)
    try:
        result = json.loads(AdaptationFolder(adaptation).result.read_text(encoding="utf-8"))
    except (OSError, ValueError) as exc:
        raise RunFolderError(f"corrupt adaptation ({exc})", file=adaptation) from None
    out.parent.mkdir(parents=True, exist_ok=True)
    return adaptation_curve(result, out, fresh_m=fresh_m)


def browser() -> str | None:
    """The first of ``CHROMIUM`` on the PATH, or None."""
    return next((path for name in CHROMIUM if (path := shutil.which(name))), None)


def report_page(run: Path) -> Path:
    """The page ``qdsega report`` wrote into ``run`` (a run's folder or an adaptation's).

    Raises:
        RunFolderError: there is none.
    """
    page = run / RunFolder.REPORT
    if not page.is_file():
        raise RunFolderError(f"no {RunFolder.REPORT}: write it with qdsega report", file=run)
    return page


def screenshot(page: Path, out: Path, *, chromium: str, window: tuple[int, int] = WINDOW) -> Path:
    """``page`` as headless ``chromium`` shows it in a ``window`` (px), saved to ``out`` in 256
    colours.

    Raises:
        RuntimeError: Chromium failed or wrote no picture.
    """
    with tempfile.TemporaryDirectory() as scratch:
        shot = Path(scratch) / "shot.png"
        command = [
            chromium, "--headless", "--no-sandbox", "--disable-gpu", "--hide-scrollbars",
            f"--user-data-dir={scratch}/profile", f"--screenshot={shot}",
            f"--window-size={window[0]},{window[1]}", page.resolve().as_uri(),
        ]  # fmt: skip
        done = subprocess.run(command, capture_output=True, text=True, timeout=120, check=False)
        if done.returncode != 0 or not shot.is_file():
            last = (done.stderr.strip().splitlines() or ["no message"])[-1]
            raise RuntimeError(f"{chromium} exited {done.returncode} without a picture: {last}")
        pixels = np.asarray(Image.open(shot).convert("RGB"))
        save_png(pixels, out, colours=256, method=Image.Quantize.MEDIANCUT)
    return out


def window_size(text: str) -> tuple[int, int]:
    """``WIDTHxHEIGHT`` in pixels, each from 100 to 10000."""
    try:
        width, height = (int(part) for part in text.split("x"))
    except ValueError:
        raise argparse.ArgumentTypeError(f"not WIDTHxHEIGHT: {text!r}") from None
    if not (100 <= width <= 10000 and 100 <= height <= 10000):
        raise argparse.ArgumentTypeError(f"each side from 100 to 10000 px: {text!r}")
    return width, height


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    commands = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")
    commands.add_parser("loop", help="QDSEGA's generation loop")
    commands.add_parser("memo", help="memo mode's pipeline")
    archive = commands.add_parser("archive", help="a repertoire's archive as heat maps")
    archive.add_argument("folder", type=Path, metavar="REPERTOIRE", help="of qdsega repertoire")
    adaptation = commands.add_parser("adaptation", help="an adaptation's curve")
    adaptation.add_argument("folder", type=Path, metavar="ADAPT", help="of qdsega adapt")
    adaptation.add_argument(
        "--fresh", type=Path, metavar="RUN", help="a fresh run of the changed body: its F drawn"
    )
    report = commands.add_parser("report", help="a screenshot of a run's report.html")
    report.add_argument("folder", type=Path, metavar="RUN", help="a folder with report.html")
    report.add_argument(
        "--window", type=window_size, default=WINDOW, metavar="WxH", help="px (1200x900)"
    )
    for command in commands.choices.values():
        command.add_argument("--out", type=Path, metavar="FILE.png", help="default docs/figures/")
    args = parser.parse_args()
    out = args.out or FIGURES / NAMES[args.command]
    try:
        if args.command == "loop":
            written = draw_loop(out)
        elif args.command == "memo":
            written = draw_memo(out)
        elif args.command == "archive":
            written = draw_archive(args.folder, out)
        elif args.command == "adaptation":
            written = draw_adaptation(args.folder, out, fresh=args.fresh)
        else:
            page = report_page(args.folder)
            chromium = browser()
            if chromium is None:
                names = ", ".join(CHROMIUM)
                print(f"diagrams.py report: error: no Chromium on the PATH ({names}); install "
                      "one to take the screenshot", file=sys.stderr)  # fmt: skip
                return 2
            written = screenshot(page, out, chromium=chromium, window=args.window)
    except QdsegaError as exc:
        print(f"diagrams.py {args.command}: error: {exc}", file=sys.stderr)
        return 2
    except RuntimeError as exc:  # Chromium failed: not the input's fault
        print(f"diagrams.py {args.command}: error: {exc}", file=sys.stderr)
        return 1
    print(f"{written} ({written.stat().st_size / 1000:.0f} kB)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
