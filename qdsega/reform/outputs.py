"""What a reform leaves its user: the winner's formation file and run (its video, figures and
report), a still of each candidate learnt to the end, the plan with a picture of the body
before and after each step, ``reform.md`` and ``plan.md``, and one page that shows all of it
(``reform.html``)."""

from __future__ import annotations

import html
import shutil
from collections.abc import Callable
from pathlib import Path
from typing import Any

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

from qdsega.analysis.plots import plot_run
from qdsega.analysis.render import final_still, render_adaptation, render_run, rest_still
from qdsega.analysis.report import data_uri, html_table, videos_html, write_page, write_report
from qdsega.atomic import replaced_atomically
from qdsega.description import load_formation
from qdsega.reform.arrangement import Arrangement, Move
from qdsega.reform.candidates import Candidate, Candidates
from qdsega.reform.folder import ReformFolder
from qdsega.simulation.camera import CameraConfig
from qdsega.training.formation_copy import load_run_world
from qdsega.training.run_folder import RunFolder

STILL = CameraConfig(width=480, height=360)
"""A learnt candidate's still: where its evaluated trial ended."""
PLAN_CAMERA = CameraConfig(width=360, height=270, pitch_deg=50.0)
"""A body at rest in the plan, seen from behind and above."""


def count_moves(n: int) -> str:
    """``1 move``, ``4 moves``."""
    return f"{n} move{'s' * (n != 1)}"


def write_outputs(
    record: dict[str, Any],
    candidates: Candidates,
    folder: ReformFolder,
    *,
    log: Callable[[str], None],
) -> None:
    """Everything but ``reform.json`` for a finished reform's ``record``."""
    winner = candidates.by_name(record["winner"]["name"])
    shutil.copyfile(folder.candidate(winner.name), folder.winner)
    run, adaptation = record["winner"]["run"], record["winner"].get("adaptation")
    if run is not None:
        log(f"qdsega reform: filming {winner.name}, its figures and report")
        render_run(Path(run), Path(run) / RunFolder.VIDEO, CameraConfig())
        plot_run(Path(run))
        write_report(Path(run))
    elif adaptation is not None:  # the body as it is, with the gait adapt found
        log(f"qdsega reform: filming the gait adapted to {winner.name}, and its report")
        body = load_formation(folder.candidate(winner.name))
        world = load_run_world(folder.run(winner.name))
        render_adaptation(Path(adaptation), body, world, CameraConfig())
        write_report(Path(adaptation))
    stills = {}
    for row in record["candidates"]:
        if row["distance_m"] is not None:
            stills[row["name"]] = folder.still(row["name"])
            _save(final_still(folder.run(row["name"]), STILL), stills[row["name"]])
    pictures = []
    for k, state in enumerate(_states(candidates.material.start(), winner.moves)):
        pictures.append(folder.plan_picture(k))
        _save(rest_still(state.formation(f"step{k}", ""), PLAN_CAMERA), pictures[-1])
    with replaced_atomically(folder.summary) as partial:
        partial.write_text(_summary(record, folder), encoding="utf-8")
    with replaced_atomically(folder.plan) as partial:
        partial.write_text(_plan(record, winner, pictures, folder), encoding="utf-8")
    _page(record, winner, stills, pictures, folder)


def _states(start: Arrangement, moves: tuple[Move, ...]) -> list[Arrangement]:
    """The body before the first move and after each."""
    states = [start]
    for move in moves:
        states.append(states[-1].moved(move))
    return states


def _save(image: np.ndarray, file: Path) -> None:
    file.parent.mkdir(parents=True, exist_ok=True)
    with replaced_atomically(file) as partial:
        plt.imsave(partial, image, format="png")


def _metres(value: float | None) -> str:
    return "" if value is None else f"{value:.3f}"


def _seconds(value: float | None) -> str:
    return "" if value is None else f"{value:.0f}"


def _step(move: Move, state: Arrangement) -> str:
    """One step of the plan in words: the unit, what hangs from it, where from and to."""
    carried = [n for n in state.subtree(move.unit) if n != move.unit]
    what = move.unit + (f" (with {', '.join(carried)})" if carried else "")
    leaves = "the spares" if move.leaves is None else f"connector {move.leaves}"
    takes = "set it aside" if move.takes is None else f"attach it at connector {move.takes}"
    return f"detach {what} from {leaves}; {takes}"


def _sentence(text: str) -> str:
    return text[:1].upper() + text[1:]


def _headline(record: dict[str, Any]) -> str:
    winner, current = record["winner"], record["current"]
    adapted = current["adapted"]
    versus = [f"relearnt as it is {_metres(current['relearnt_m'])} m"]
    if adapted is not None:
        versus.append(f"adapted as it is {_metres(adapted['distance_m'])} m")
    else:
        versus.append("not adapted (no --repertoire given)")
    what = (
        f"re-form into {winner['name']} ({count_moves(len(winner['moves']))})"
        if winner["reformed"]
        else f"keep the body ({winner['how']})"
    )
    return f"{what}: {_metres(winner['distance_m'])} m in exact physics; " + ", ".join(versus)


def _summary(record: dict[str, Any], folder: ReformFolder) -> str:
    inputs = record["inputs"]
    winner, plan, page = (f.name for f in (folder.winner, folder.plan, folder.page))
    screen = inputs["settings"]["screen"]
    lines = [
        f"# Re-forming {inputs['formation']} in {inputs['world']}",
        "",
        f"**{_headline(record)}.** Wall time {record['wall_s'] / 60:.1f} min.",
        "",
        f"The winner's formation: [{winner}]({winner}); how to get there: [{plan}]({plan}); "
        f"everything on one page: [{page}]({page}).",
        "",
        f"Every candidate: the screening estimate is its run's best greedy policy in exact "
        f"physics after {screen} generations; the exact distance is the full run's result, "
        "evaluated in exact physics.",
        "",
        "| candidate | how | moves | units | joints | estimate (m) | exact (m) | screening (s) "
        "| learning (s) | dropped |",
        "|---|---|---|---|---|---|---|---|---|---|",
    ]
    for row in record["candidates"]:
        moves = "; ".join(
            f"{m['unit']}: {m['leaves'] or 'the spares'} -> {m['takes'] or 'the spares'}"
            for m in row["moves"]
        )
        lines.append(
            f"| {row['name']} | {row['how']} | {moves or '-'} | {row['units']} | {row['joints']} "
            f"| {_metres(row['estimate_m'])} | {_metres(row['distance_m'])} "
            f"| {_seconds(row['screen_s'])} | {_seconds(row['learn_s'])} "
            f"| {(row['dropped'] or '').replace('|', '/')} |"
        )
    return "\n".join(lines) + "\n"


def _plan(
    record: dict[str, Any], winner: Candidate, pictures: list[Path], folder: ReformFolder
) -> str:
    out = folder.path
    inputs = record["inputs"]
    moves = winner.moves
    lines = [
        f"# Plan: {inputs['formation']} to {winner.name}",
        "",
        f"{count_moves(len(moves))}, the fewest that reach this body "
        "(each detaches a unit with everything that hangs from it and attaches it elsewhere, "
        "or sets it aside).",
        "",
        f"![the body as it is]({pictures[0].relative_to(out)})",
    ]
    states = _states(winner.arrangement.material.start(), moves)
    for k, move in enumerate(moves, start=1):
        lines += [
            "",
            f"{k}. {_sentence(_step(move, states[k - 1]))}.",
            "",
            f"   ![before]({pictures[k - 1].relative_to(out)}) "
            f"![after]({pictures[k].relative_to(out)})",
        ]
    if not moves:
        lines += ["", "Nothing to move: the body as it is goes farthest."]
    return "\n".join(lines) + "\n"


def _page(
    record: dict[str, Any],
    winner: Candidate,
    stills: dict[str, Path],
    pictures: list[Path],
    folder: ReformFolder,
) -> Path:
    inputs = record["inputs"]
    title = f"qdsega reform: {inputs['formation']} in {inputs['world']}"
    shown = record["winner"]["run"] or record["winner"].get("adaptation")
    video = videos_html(Path(shown)) if shown is not None else "<p class='note'>No run.</p>"
    head = (
        "<tr><th>candidate</th><th>how</th><th>moves</th><th>estimate (m)</th>"
        "<th>exact (m)</th><th>dropped</th></tr>"
    )
    rows = "".join(
        f"<tr><td>{r['name']}</td><td>{html.escape(r['how'])}</td>"
        f"<td>{len(r['moves'])}</td><td>{_metres(r['estimate_m'])}</td>"
        f"<td>{_metres(r['distance_m'])}</td><td>{html.escape(r['dropped'] or '')}</td></tr>"
        for r in record["candidates"]
    )
    by_name = {r["name"]: r for r in record["candidates"]}
    figures = "".join(
        f"<figure><img src='{data_uri(file)}'><figcaption>{name}: "
        f"{_metres(by_name[name]['distance_m'])} m</figcaption></figure>"
        for name, file in stills.items()
    )
    states = _states(winner.arrangement.material.start(), winner.moves)
    steps = [
        f"<figure><img src='{data_uri(pictures[0])}'><figcaption>as it is</figcaption></figure>"
    ]
    for k, move in enumerate(winner.moves, start=1):
        steps.append(
            f"<h3>{k}. {html.escape(_step(move, states[k - 1]))}</h3>"
            f"<img src='{data_uri(pictures[k - 1])}' width='45%'> "
            f"<img src='{data_uri(pictures[k])}' width='45%'>"
        )
    summary = {
        "verdict": _headline(record),
        "wall time (min)": record["wall_s"] / 60,
        "winner's formation": str(folder.winner),
        "winner's run": shown or "",
    }
    parts = [
        f"<h1>{html.escape(title)}</h1>",
        html_table(summary),
        "<h2>The winner in exact physics</h2>",
        video,
        f"<h2>Plan: {len(winner.moves)} moves</h2>",
        *steps,
        "<h2>Candidates learnt to the end (where their trial ended)</h2>",
        figures,
        "<h2>Every candidate</h2>",
        f"<table>{head}{rows}</table>",
    ]
    return write_page((title, parts), folder.page)
