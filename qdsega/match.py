"""The body for the world: every formation trained and evaluated in every world (a sweep), then
one matrix of exact distances and ratios to each cell's best reference, the best body of each
world, a heatmap and an HTML page with a still of each cell.

The runs are a sweep's (:mod:`qdsega.sweep`): resumable, on local processes or Ray. A cell is
the median over its seeds; a body that cannot start in a world (it starts inside an
obstacle) or whose run failed is an empty cell with the reason.
"""

from __future__ import annotations

import base64
import html
import io
import statistics
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
import yaml

from qdsega.atomic import replaced_atomically
from qdsega.training.config import SCREENING_GENERATIONS
from qdsega.training.run import PREDICTION_TOLERANCE

SCREEN = {"agent": {"genetic": {"generations": SCREENING_GENERATIONS}}}
"""The screening budget: each body's own preset, cut to its first generations."""


@dataclass(frozen=True)
class Cell:
    """One formation in one world: the median over seeds of the exact distance (m) and of the
    ratio to the best reference, the run folder of the median seed, or why it is empty; and the
    largest relative error of the memo table's prediction over its seeds (None: no prediction,
    or 0 m exact)."""

    distance_m: float | None
    ratio: float | None
    run: str | None
    error: str | None
    prediction_error: float | None = None


def match_grid(
    formations: Sequence[str],
    worlds: Sequence[str],
    *,
    seeds: Sequence[int],
    preset: str | None,
    settings: dict[str, Any],
    reference_trials: int | None,
) -> str:
    """The sweep grid (YAML text) of every formation in every world, memo mode."""
    grid: dict[str, Any] = {
        "formations": list(formations),
        "worlds": list(worlds),
        "seeds": list(seeds),
        "sim": "memo",
        "configs": {"match": settings},
    }
    if preset is not None:
        grid["presets"] = [preset]
    if reference_trials is not None:
        grid["reference_trials"] = reference_trials
    return yaml.safe_dump(grid, sort_keys=False)


def matrix(rows: Sequence[dict[str, Any]]) -> dict[tuple[str, str], Cell]:
    """The cells of a sweep's table, by (formation, world)."""
    by_cell: dict[tuple[str, str], list[dict[str, Any]]] = {}
    for row in rows:
        by_cell.setdefault((row["formation"], row["world"]), []).append(row)
    cells = {}
    for key, group in by_cell.items():
        ok = sorted((r for r in group if r["status"] == "ok"), key=lambda r: r["distance_m"])
        if not ok:
            cells[key] = Cell(None, None, None, group[0]["error"])
            continue
        median = ok[(len(ok) - 1) // 2]
        ratios = [r["ratio"] for r in ok if r["ratio"] is not None]
        errors = [
            (r["memo_prediction_m"] - r["distance_m"]) / abs(r["distance_m"])
            for r in ok
            if r.get("memo_prediction_m") is not None and r["distance_m"] != 0
        ]
        cells[key] = Cell(
            distance_m=statistics.median(r["distance_m"] for r in ok),
            ratio=statistics.median(ratios) if ratios else None,
            run=median["run"],
            error=None,
            prediction_error=max(errors, key=abs) if errors else None,
        )
    return cells


def best_bodies(cells: dict[tuple[str, str], Cell]) -> dict[str, str | None]:
    """The formation that went farthest in each world (None where none could move)."""
    best: dict[str, tuple[float, str] | None] = {}
    for (formation, world), cell in cells.items():
        current = best.setdefault(world, None)
        if cell.distance_m is not None and (current is None or cell.distance_m > current[0]):
            best[world] = (cell.distance_m, formation)
    return {world: None if b is None else b[1] for world, b in best.items()}


def write_matrix(
    cells: dict[tuple[str, str], Cell],
    formations: Sequence[str],
    worlds: Sequence[str],
    out: Path,
    stills: dict[tuple[str, str], np.ndarray],
) -> tuple[Path, Path, Path]:
    """``OUT/match.md``, ``OUT/match.png`` (a heatmap of the distances) and
    ``OUT/match.html`` (the table with a still of each cell)."""
    best = best_bodies(cells)
    markdown = _markdown(cells, formations, worlds, best)
    with replaced_atomically(out / "match.md") as partial:
        partial.write_text(markdown, encoding="utf-8")
    figure = out / "match.png"
    _heatmap(cells, formations, worlds, figure)
    page = _page(cells, formations, worlds, best, stills, figure)
    with replaced_atomically(out / "match.html") as partial:
        partial.write_text(page, encoding="utf-8")
    return out / "match.md", figure, out / "match.html"


def _text(cell: Cell | None) -> str:
    if cell is None:
        return ""
    if cell.distance_m is None:
        return "cannot start" if cell.error and "inside an obstacle" in cell.error else "failed"
    ratio = "" if cell.ratio is None else f" ({cell.ratio:.2f})"
    return f"{cell.distance_m:.3f}{ratio}"


def _markdown(
    cells: dict[tuple[str, str], Cell],
    formations: Sequence[str],
    worlds: Sequence[str],
    best: dict[str, str | None],
) -> str:
    lines = [
        "Exact distance toward the light (m), median over seeds, and in brackets its ratio to "
        "the cell's best reference gait.",
        "",
        "| formation | " + " | ".join(worlds) + " |",
        "|---|" + "---|" * len(worlds),
    ]
    for formation in formations:
        marked = []
        for world in worlds:
            text = _text(cells.get((formation, world)))
            marked.append(f"**{text}**" if best.get(world) == formation else text)
        lines.append(f"| {formation} | " + " | ".join(marked) + " |")
    lines += ["", "| world | best body |", "|---|---|"]
    lines += [f"| {w} | {best.get(w) or 'none moved'} |" for w in worlds]
    errors = [c.prediction_error for c in cells.values() if c.prediction_error is not None]
    if errors:
        held = sum(abs(e) <= PREDICTION_TOLERANCE for e in errors)
        lines += [
            "",
            "The memo table's prediction of the learnt policy against exact physics, the worst "
            f"seed's relative error: within {PREDICTION_TOLERANCE:.0%} in {held} of "
            f"{len(errors)} cells.",
            "",
            "| formation | " + " | ".join(worlds) + " |",
            "|---|" + "---|" * len(worlds),
        ]
        for formation in formations:
            row = [_error_text(cells.get((formation, world))) for world in worlds]
            lines.append(f"| {formation} | " + " | ".join(row) + " |")
    return "\n".join(lines) + "\n"


def _error_text(cell: Cell | None) -> str:
    if cell is None or cell.prediction_error is None:
        return ""
    return f"{cell.prediction_error:+.0%}"


def _heatmap(
    cells: dict[tuple[str, str], Cell],
    formations: Sequence[str],
    worlds: Sequence[str],
    file: Path,
) -> None:
    values = np.full((len(formations), len(worlds)), np.nan)
    for i, formation in enumerate(formations):
        for j, world in enumerate(worlds):
            cell = cells.get((formation, world))
            if cell is not None and cell.distance_m is not None:
                values[i, j] = cell.distance_m
    fig, ax = plt.subplots(figsize=(1.4 * len(worlds) + 2.5, 0.6 * len(formations) + 1.8))
    image = ax.imshow(values, cmap="viridis", aspect="auto")  # cells fill the figure
    ax.set_xticks(range(len(worlds)), worlds, rotation=30, ha="right")
    ax.set_yticks(range(len(formations)), formations)
    for i in range(len(formations)):
        for j in range(len(worlds)):
            empty = np.isnan(values[i, j])
            text = "-" if empty else f"{values[i, j]:.2f}"
            colour = "black" if empty else "white"  # an empty cell is drawn white
            ax.text(j, i, text, ha="center", va="center", color=colour, fontsize=9)
    fig.colorbar(image, ax=ax, label="exact distance (m)")
    ax.set_title("which body for which world")
    fig.tight_layout()
    with replaced_atomically(file) as partial:
        fig.savefig(partial, format="png", dpi=110)
    plt.close(fig)


def _png(image: np.ndarray | Path) -> str:
    if isinstance(image, Path):
        data = image.read_bytes()
    else:
        buffer = io.BytesIO()
        plt.imsave(buffer, image, format="png")
        data = buffer.getvalue()
    return "data:image/png;base64," + base64.b64encode(data).decode()


def _page(
    cells: dict[tuple[str, str], Cell],
    formations: Sequence[str],
    worlds: Sequence[str],
    best: dict[str, str | None],
    stills: dict[tuple[str, str], np.ndarray],
    figure: Path,
) -> str:
    head = "".join(f"<th>{html.escape(w)}</th>" for w in worlds)
    rows = []
    for formation in formations:
        tds = []
        for world in worlds:
            cell = cells.get((formation, world))
            still = stills.get((formation, world))
            picture = "" if still is None else f'<br><img src="{_png(still)}" width="320">'
            mark = ' class="best"' if best.get(world) == formation else ""
            tds.append(f"<td{mark}>{html.escape(_text(cell))}{picture}</td>")
        rows.append(f"<tr><th>{html.escape(formation)}</th>{''.join(tds)}</tr>")
    bests = "".join(
        f"<li>{html.escape(w)}: <b>{html.escape(best.get(w) or 'none moved')}</b></li>"
        for w in worlds
    )
    return (
        "<!DOCTYPE html><html><head><meta charset='utf-8'><title>qdsega match</title><style>"
        "body{font-family:sans-serif;margin:2em}td,th{border:1px solid #ccc;padding:6px;"
        "text-align:center;vertical-align:top}td.best{background:#e8f6e0}</style></head><body>"
        "<h1>Which body for which world</h1><p>Exact distance toward the light (m), median "
        "over seeds, and its ratio to the cell's best reference gait; the best body of each "
        "world is green. Each still is the end of the cell's evaluated trial.</p>"
        f"<table><tr><th></th>{head}</tr>{''.join(rows)}</table>"
        f"<h2>Best body per world</h2><ul>{bests}</ul>"
        f'<img src="{_png(figure)}"></body></html>\n'
    )
