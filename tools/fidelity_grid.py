"""Train and evaluate formations x seeds with the README's presets, then print the tables.

Usage: .venv/bin/python tools/fidelity_grid.py [--formations snake5 ...] [--seeds 0 1 2 3 4]
                                               [--out runs/grid] [--workers 2]

Each run goes to ``OUT/FORMATION-seedS`` in memo mode, with ``paper-snake`` for a legless
formation and ``memo-legged`` for a legged one; a finished run is kept, an unfinished one
resumed, a missing evaluation made. Then ``tools/formation_table.py``'s tables are printed and
written to ``OUT/table.md``.
"""

from __future__ import annotations

import argparse
import subprocess
import sys
from pathlib import Path

from formation_table import tables

from qdsega.description import load_formation, resolve_formation
from qdsega.training.config import default_preset


def preset_of(name: str) -> str:
    """The README's memo-mode preset for a shipped formation (or a formation file)."""
    return default_preset(load_formation(resolve_formation(Path(name))), "memo")


def qdsega(*args: str | Path) -> None:
    """Run ``qdsega ARGS``; stop the grid if it fails."""
    command = [sys.executable, "-m", "qdsega.cli", *map(str, args)]
    print("$", " ".join(command[2:]), flush=True)
    subprocess.run(command, check=True)


def train(name: str, seed: int, run: Path, workers: int, *extra: str | Path) -> None:
    """Make the finished run folder ``run``: kept if finished, resumed if not, else trained in
    memo mode with the README's preset for ``name``."""
    if (run / "summary.json").is_file():
        return
    if (run / "config.yaml").is_file():
        qdsega("train", "--resume", run)
        return
    qdsega("train", name, "--sim", "memo", "--preset", preset_of(name), "--seed", str(seed),
           "--workers", str(workers), "--out", run, *extra)  # fmt: skip


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument(
        "--formations", nargs="+", default=["snake5", "snake10", "quadruped", "hexapod", "legged12"]
    )
    parser.add_argument("--seeds", nargs="+", type=int, default=[0, 1, 2, 3, 4])
    parser.add_argument("--out", type=Path, default=Path("runs/grid"))
    parser.add_argument("--workers", type=int, default=2)
    args = parser.parse_args()
    folders = []
    for name in args.formations:
        for seed in args.seeds:
            run = args.out / f"{Path(name).stem}-seed{seed}"
            train(name, seed, run, args.workers)
            if not (run / "evaluation.json").is_file():
                qdsega("evaluate", run)
            folders.append(run)
    text = tables(folders)
    (args.out / "table.md").write_text(text + "\n", encoding="utf-8")
    print(text)


if __name__ == "__main__":
    main()
