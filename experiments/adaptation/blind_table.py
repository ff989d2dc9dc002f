"""Adaptation with the damage known (mapped) and unknown (blind), side by side.

Usage: .venv/bin/python experiments/adaptation/blind_table.py
           --change REPERTOIRE CHANGED [--change ...] [--trials 20] [--out runs/blind]

For each change (a repertoire folder of the intact body, and the changed body: a file or a
shipped name) the repertoire is adapted twice, into ``OUT/CHANGED-mapped`` and
``OUT/CHANGED-blind``: its gaits mapped onto the changed body (``qdsega adapt --formation``,
:func:`qdsega.adaptation.adapt.adapt`), and the intact gaits played unmapped on the changed
body hidden from the search (``qdsega adapt --blind``, :func:`qdsega.adaptation.adapt.
adapt_blind`). The table, printed and written to ``OUT/table.md``, gives each one's trials,
the distance found in exact physics and its wall time, whether the two played the same trials,
and how many of the repertoire's gaits stay distinct once mapped (a lost or locked joint makes
gaits that differ only there one gait; the mapped search does not use it).
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path
from typing import Any

from qdsega.adaptation.adapt import MappedRepertoire, adapt, adapt_blind
from qdsega.description import load_formation, resolve_formation

COLUMNS = (
    "change",
    "repertoire: gaits (distinct once mapped)",
    "mapped: trials, found (m)",
    "blind: trials, found (m)",
    "same trials",
    "wall mapped / blind (s)",
)


def row(repertoire: Path, changed: str, trials: int, out: Path) -> dict[str, Any]:
    body = load_formation(resolve_formation(changed))
    mapped = MappedRepertoire.of(repertoire, body)
    distinct = len({tuple(map(tuple, g)) for g in mapped.gaits})
    start = time.perf_counter()
    known = adapt(repertoire, body, out / f"{body.name}-mapped", trials=trials)
    middle = time.perf_counter()
    blind = adapt_blind(repertoire, body, out / f"{body.name}-blind", trials=trials)
    end = time.perf_counter()

    def played(result: dict[str, Any]) -> list[tuple[int, float]]:
        return [(t["cell"], t["distance_m"]) for t in result["trials"]]

    return {
        "change": f"{mapped.record['formation']} -> `{body.name}`",
        "gaits": f"{len(mapped.gaits)} ({distinct})",
        "mapped": f"{len(known['trials'])}, {known['distance_m']:.3f}",
        "blind": f"{len(blind['trials'])}, {blind['distance_m']:.3f}",
        "same": "yes" if played(known) == played(blind) else "no",
        "wall": f"{middle - start:.1f} / {end - middle:.1f}",
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument(
        "--change", nargs=2, action="append", required=True, metavar=("REPERTOIRE", "CHANGED")
    )
    parser.add_argument("--trials", type=int, default=20)
    parser.add_argument("--out", type=Path, default=Path("runs/blind"))
    args = parser.parse_args()
    lines = ["| " + " | ".join(COLUMNS) + " |", "|" + "---|" * len(COLUMNS)]
    for repertoire, changed in args.change:
        cells = row(Path(repertoire), changed, args.trials, args.out).values()
        lines.append("| " + " | ".join(cells) + " |")
        print(lines[-1], flush=True)
    args.out.mkdir(parents=True, exist_ok=True)
    (args.out / "table.md").write_text("\n".join(lines) + "\n", encoding="utf-8")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
