"""The table of finished reforms: per reform its winner against the intact body, the body as it
is adapted and relearnt, and the medians per change.

Usage: .venv/bin/python experiments/reform/reform_table.py runs/reform/*-seed* \
        --intact quadruped_tripod=runs/intact/quadruped-seed{seed} \
        --intact hexapod_lost_leg=runs/intact/hexapod-seed{seed} [--out table.md]

Each reform folder is one ``qdsega reform`` (its ``reform.json``); ``--intact CHANGED=PATTERN``
names the intact body's finished run of the same seed, whose ``distance_m`` the winner is
measured against (``{seed}`` is the reform's seed).
"""

from __future__ import annotations

import argparse
import json
import statistics
from pathlib import Path
from typing import Any

COLUMNS = (
    "change",
    "seed",
    "screened",
    "winner",
    "moves",
    "exact (m)",
    "intact (m)",
    "/ intact",
    "adapted as it is (m)",
    "/ adapted",
    "relearnt as it is (m)",
    "/ relearnt",
    "wall (min)",
)


def row(folder: Path, intact: dict[str, str]) -> dict[str, Any]:
    record = json.loads((folder / "reform.json").read_text(encoding="utf-8"))
    inputs, winner, current = record["inputs"], record["winner"], record["current"]
    seed = inputs["settings"]["seed"]
    pattern = intact.get(inputs["formation"])
    intact_m = None
    if pattern is not None:
        summary = Path(pattern.format(seed=seed)) / "summary.json"
        intact_m = json.loads(summary.read_text(encoding="utf-8"))["distance_m"]
    adapted_m = None if current["adapted"] is None else current["adapted"]["distance_m"]
    moves = "; ".join(f"{m['unit']}: {m['leaves']} -> {m['takes']}" for m in winner["moves"])
    return {
        "change": inputs["formation"]
        + ("" if inputs["world"] == "flat" else f" in {inputs['world']}"),
        "seed": seed,
        "screened": sum(r["estimate_m"] is not None for r in record["candidates"]),
        "winner": winner["name"] + ("" if winner["reformed"] else f" ({winner['how']})"),
        "moves": moves or "-",
        "exact (m)": winner["distance_m"],
        "intact (m)": intact_m,
        "/ intact": _ratio(winner["distance_m"], intact_m),
        "adapted as it is (m)": adapted_m,
        "/ adapted": _ratio(winner["distance_m"], adapted_m),
        "relearnt as it is (m)": current["relearnt_m"],
        "/ relearnt": _ratio(winner["distance_m"], current["relearnt_m"]),
        "wall (min)": record["wall_s"] / 60,
    }


def _in(world: str) -> str:
    return "" if world == "flat" else f" in {world}"


def _ratio(value: float, base: float | None) -> float | None:
    return None if base is None or base <= 0 else value / base


def _cell(value: Any) -> str:
    if value is None:
        return ""
    return f"{value:.3f}" if isinstance(value, float) else str(value)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("reforms", type=Path, nargs="+")
    parser.add_argument("--intact", action="append", default=[], metavar="CHANGED=PATTERN")
    parser.add_argument("--out", type=Path)
    args = parser.parse_args()
    intact = dict(given.split("=", 1) for given in args.intact)
    rows = [row(folder, intact) for folder in args.reforms]
    lines = ["| " + " | ".join(COLUMNS) + " |", "|" + "---|" * len(COLUMNS)]
    lines += ["| " + " | ".join(_cell(r[c]) for c in COLUMNS) + " |" for r in rows]
    lines += ["", "Medians per change:", ""]
    numbers = [c for c in COLUMNS if c.startswith("/") or c.endswith("(m)") or c == "wall (min)"]
    lines += ["| change | " + " | ".join(numbers) + " |", "|---|" + "---|" * len(numbers)]
    for change in dict.fromkeys(r["change"] for r in rows):
        group = [r for r in rows if r["change"] == change]
        medians = []
        for column in numbers:
            values = [r[column] for r in group if r[column] is not None]
            medians.append(_cell(statistics.median(values)) if values else "")
        lines.append(f"| {change} | " + " | ".join(medians) + " |")
    text = "\n".join(lines) + "\n"
    if args.out is not None:
        args.out.write_text(text, encoding="utf-8")
    print(text)


if __name__ == "__main__":
    main()
