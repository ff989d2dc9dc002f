"""One self-contained HTML page about a run: summary, evaluation, figures, video, configuration
and the formation (the run's copy of its file); or about an adaptation (``qdsega adapt``'s
folder): what it found, its curve, its video and every trial.

Figures and the video are embedded as data URIs, so the page can be mailed or uploaded alone.
The page shows what the run folder holds: figures come from ``qdsega plot``, the evaluation
from ``qdsega evaluate``, videos (``*.mp4``, ``*.gif``) from ``qdsega render -o RUN/...``.
"""

from __future__ import annotations

import base64
import html
import json
from pathlib import Path
from typing import Any

from qdsega.adaptation.adapt import MODES, is_adaptation
from qdsega.adaptation.folders import AdaptationFolder
from qdsega.analysis.plots import FIGURES, body_in_world
from qdsega.atomic import replaced_atomically
from qdsega.errors import RunFolderError
from qdsega.training.formation_copy import read_formation_record
from qdsega.training.joint_mapping import describe
from qdsega.training.run_folder import RunFolder

_MEDIA = {".png": "image/png", ".gif": "image/gif", ".mp4": "video/mp4"}
_STYLE = """
body { font-family: system-ui, sans-serif; max-width: 960px; margin: 2em auto; padding: 0 1em;
       color: #222; }
table { border-collapse: collapse; margin: 0.5em 0 1.5em; }
td, th { border: 1px solid #ccc; padding: 0.25em 0.6em; text-align: left; }
th { background: #f3f3f3; }
img, video { max-width: 100%; border: 1px solid #ddd; margin: 0.5em 0; }
pre { background: #f6f6f6; padding: 0.8em; overflow-x: auto; }
.note { color: #777; }
"""


def write_report(run: Path | str, out: Path | None = None) -> Path:
    """Write the report of ``run`` (a run folder or an adaptation's) to ``out`` (default
    ``RUN/report.html``); return its path.

    Raises:
        RunFolderError: not a finished run folder, or its files do not parse.
    """
    run = Path(run)
    if is_adaptation(run):
        return write_page(_adaptation(run), out or AdaptationFolder(run).report)
    folder = RunFolder(run)
    folder.require_finished(folder.CONFIG)
    summary, evaluation = folder.read_summary(), folder.read_evaluation()
    record = read_formation_record(run)
    try:
        config = (folder / folder.CONFIG).read_text(encoding="utf-8")
        formation = (folder / folder.FORMATION_DIR / record.formation).read_text(encoding="utf-8")
    except OSError as exc:
        raise RunFolderError(f"corrupt run folder ({exc})", file=run) from None
    run_of = f"{summary.get('sim')}, seed {summary.get('seed')}"
    title = f"qdsega run: {body_in_world(summary)} ({run_of})"
    parts = [
        f"<h1>{html.escape(title)}</h1>",
        "<h2>Summary</h2>",
        html_table({k: v for k, v in summary.items() if k != "warm_start"}),
        *_warm_start(summary.get("warm_start")),
        "<h2>Evaluation with exact physics</h2>",
        _evaluation(evaluation, run),
        *_transfers(run, summary.get("world", "flat")),
        "<h2>Video</h2>",
        videos_html(run),
        "<h2>Figures</h2>",
        _figures(run),
        "<h2>Configuration</h2>",
        f"<pre>{html.escape(config)}</pre>",
        f"<h2>Formation: {html.escape(record.formation)}</h2>",
        f"<p class='note'>The run's copy; sha256 of it and its unit files {record.sha256}.</p>",
        f"<pre>{html.escape(formation)}</pre>",
    ]
    return write_page((title, parts), out or folder / folder.REPORT)


def write_page(content: tuple[str, list[str]], out: Path) -> Path:
    """Write the page of ``content`` (its title, its parts' HTML) to ``out``."""
    title, parts = content
    page = (
        f"<!DOCTYPE html>\n<html lang='en'><head><meta charset='utf-8'>"
        f"<title>{html.escape(title)}</title><style>{_STYLE}</style></head><body>\n"
        + "\n".join(parts)
        + "\n</body></html>\n"
    )
    with replaced_atomically(out) as partial:
        partial.write_text(page, encoding="utf-8")
    return out


def _adaptation(folder: Path) -> tuple[str, list[str]]:
    """The title and parts of an adaptation's page."""
    files = AdaptationFolder(folder)
    try:
        result = json.loads(files.result.read_text(encoding="utf-8"))
        title = f"qdsega adapt: {result['formation']} from {result['intact']}'s repertoire"
        summary = {
            "changed body": result["formation_file"] or result["formation"],
            "trials played on": result.get("played_on", MODES["mapped"]),  # older: mapped
            "repertoire": result["repertoire"],
            "world": result["world"],
            "joints": describe(result["joints"]),
            "gait found (m)": result["distance_m"],
            "found at trial": result["trial_found"],
            "trials": len(result["trials"]),
            "stopped": result["stopped"],
            "best predicted at the end (m)": result["best_predicted_m"],
            "wall time (s)": result["wall_s"],
        }
        rows = "".join(
            f"<tr><td>{k}</td><td>{t['cell']}</td><td>{t['intact_m']:.3f}</td>"
            f"<td>{t['predicted_m']:.3f}</td><td>{t['distance_m']:.3f}</td>"
            f"<td>{html.escape(t['failure'] or '')}</td></tr>"
            for k, t in enumerate(result["trials"], start=1)
        )
    except (OSError, ValueError, KeyError, TypeError) as exc:
        raise RunFolderError(f"corrupt adaptation ({exc})", file=folder) from None
    figure = (
        f"<figure><img alt='{files.curve.name}' src='{data_uri(files.curve)}'></figure>"
        if files.curve.is_file()
        else "<p class='note'>No curve.</p>"
    )
    video = f"{folder}/{files.video.name}"
    head = "<tr><th>trial</th><th>cell</th><th>on the intact body (m)</th>"
    head += "<th>predicted (m)</th><th>trial (m)</th><th>failed</th></tr>"
    return title, [
        f"<h1>{html.escape(title)}</h1>",
        "<h2>Summary</h2>",
        html_table(summary),
        "<h2>Video of the gait found</h2>",
        videos_html(folder, f"qdsega render FORMATION --postures {files.gait} -o {video}"),
        "<h2>Adaptation curve</h2>",
        figure,
        "<h2>Every trial</h2>",
        f"<table>{head}{rows}</table>",
    ]


def html_table(values: dict[str, Any]) -> str:
    """A two-column table: each key and its value."""
    rows = "".join(
        f"<tr><th>{html.escape(str(k))}</th><td>{html.escape(_format(v))}</td></tr>"
        for k, v in values.items()
    )
    return f"<table>{rows}</table>"


def _format(value: Any) -> str:
    if isinstance(value, float):
        return f"{value:.4g}"
    if isinstance(value, list | dict):
        return json.dumps(value)
    return str(value)


def _evaluation(evaluation: dict[str, Any] | None, run: Path) -> str:
    if evaluation is None:
        return f"<p class='note'>Not evaluated yet: <code>qdsega evaluate {run}</code>.</p>"
    best = evaluation["reference"]
    shown: dict[str, Any] = {
        "learnt policy, distance toward the light (m)": evaluation["distance_m"],
        "ended early because": evaluation["failure"] or "did not fail",
        "memo table predicted (m)": evaluation.get("memo_prediction_m"),
    }
    for reference in evaluation.get("references", [best]):
        won = " (best)" if reference == best else ""
        budget = reference.get("budget_trials")
        spent = "" if budget is None else f", searched in {budget} exact trials"
        shown[f"reference: {reference['kind']}{spent} (m){won}"] = reference["distance_m"]
        shown[f"{reference['kind']}: parameters"] = reference.get("params")
    shown["ratio learnt / best reference"] = evaluation["ratio"]
    wave = evaluation.get("wave")
    if wave is not None:
        shown["period (steps)"] = wave["period_steps"]
        shown["phase lag between neighbouring joints (deg)"] = wave["phase_lag_deg"]
    return html_table({k: v for k, v in shown.items() if v is not None})


def _warm_start(record: dict[str, Any] | None) -> list[str]:
    """The section on where a warm-started run started from; none for a fresh run."""
    if record is None:
        return []
    if record.get("adapt_trials") is not None:  # a gait qdsega adapt found
        shown = {
            "started from the adaptation": record["run"],
            "the gait it found, exact physics (m)": record["distance_m"],
            "in exact trials": record["adapt_trials"],
        }
    else:
        shown = {
            "started from the run": record["run"],
            "its formation": record["formation"],
            "its seed, generations": f"{record['seed']}, {record['generations']}",
            "its policy on its own body, exact physics (m)": record["distance_m"],
            "joints": describe(record["joints"]),
        }
    if record.get("handed_on_m") is not None:
        shown["its best path on this body, exact physics, before generation 1 (m)"] = record[
            "handed_on_m"
        ]
    return ["<h2>Warm start</h2>", html_table(shown)]


def _transfers(run: Path, own_world: str) -> list[str]:
    """The section on this run's policy replayed on other bodies (``evaluate --formation``)
    and judged in other worlds (``evaluate --world``); a row names a world other than
    ``own_world``, the run's."""
    rows = {}
    files = [*sorted(run.glob("evaluation-on-*.json")), *sorted(run.glob("evaluation-in-*.json"))]
    for file in files:
        try:
            result = json.loads(file.read_text(encoding="utf-8"))
            world = result.get("world", own_world)  # files from before worlds: the run's
            label = (
                result["formation"] if world == own_world else f"{result['formation']} in {world}"
            )
            failure = "" if result["failure"] is None else f" (failed: {result['failure']})"
            if "joints" in result:  # another body
                facts = describe(result["joints"])
            else:  # another world, beside its best reference there
                reference, ratio = result["reference"], result["ratio"]
                facts = f"best reference: {reference['kind']} {reference['distance_m']:.4f} m"
                facts += "" if ratio is None else f", ratio {ratio:.3f}"
            rows[label] = f"{result['distance_m']:.4f} m{failure}; {facts}"
        except (OSError, ValueError, KeyError, TypeError) as exc:
            raise RunFolderError(f"corrupt run folder ({file.name}: {exc})", file=run) from None
    if not rows:
        return []
    heading = "This policy on other bodies and in other worlds (exact physics)"
    return [f"<h2>{heading}</h2>", html_table(rows)]


def videos_html(run: Path, how: str | None = None) -> str:
    """Every video in ``run``; where there is none, ``how`` to make one (a command)."""
    files = sorted(p for p in run.iterdir() if p.suffix.lower() in (".mp4", ".gif"))
    if not files:
        how = how or f"qdsega render {run} -o {run / RunFolder.VIDEO}"
        return f"<p class='note'>No video: <code>{html.escape(how)}</code>.</p>"
    blocks = []
    for file in files:
        uri = data_uri(file)
        if file.suffix.lower() == ".mp4":
            blocks.append(f"<video controls loop muted src='{uri}'></video>")
        else:
            blocks.append(f"<img alt='{html.escape(file.name)}' src='{uri}'>")
    return "\n".join(blocks)


def _figures(run: Path) -> str:
    files = [run / name for name in FIGURES if (run / name).is_file()]
    if not files:
        return f"<p class='note'>No figures: <code>qdsega plot {run}</code>.</p>"
    return "\n".join(
        f"<figure><img alt='{html.escape(f.name)}' src='{data_uri(f)}'>"
        f"<figcaption>{html.escape(f.name)}</figcaption></figure>"
        for f in files
    )


def data_uri(file: Path) -> str:
    """``file`` (a picture or a video) as a data URI, to embed in a page."""
    encoded = base64.b64encode(file.read_bytes()).decode("ascii")
    return f"data:{_MEDIA[file.suffix.lower()]};base64,{encoded}"
