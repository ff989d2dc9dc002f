"""How well does the screening estimate rank the candidates of a reform? Every candidate the
reform screened is learnt to the end (its run resumed where screening stopped it), and the
estimate after S generations (its run's best greedy policy in exact physics by then) is
compared with the full run's result, for several S: Spearman's rank correlation (scipy's,
ties handled) and whether the full run's best is among the estimate's top 3.

Usage: .venv/bin/python experiments/reform/screening_correlation.py runs/reform-quadruped_tripod \
        --jobs 2 [--screens 1 2 4 8]
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import numpy as np
from scipy.stats import spearmanr

from qdsega.driver import run_jobs
from qdsega.progress import ProgressLine
from qdsega.reform.folder import ReformFolder
from qdsega.reform.search import CandidateJob
from qdsega.training.run_folder import RunFolder


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("reform", type=Path, help="a finished qdsega reform folder")
    parser.add_argument("--jobs", type=int, default=2)
    parser.add_argument("--screens", type=int, nargs="+", default=[1, 2, 4, 8])
    args = parser.parse_args()
    folder = ReformFolder(args.reform)
    record = json.loads(folder.record.read_text(encoding="utf-8"))
    inputs = record["inputs"]
    world = None if inputs["world_file"] is None else Path(inputs["world_file"])
    names = [r["name"] for r in record["candidates"] if r["estimate_m"] is not None]
    jobs = [
        CandidateJob(
            name=name,
            formation=folder.candidate(name),
            folder=folder.run(name),
            world=world,
            seed=inputs["settings"]["seed"],
            workers=1 if args.jobs > 1 else 2,
            until=None,
            reference_trials=0,
            config=folder.config if folder.config.is_file() else None,
        )
        for name in names
    ]
    errors = run_jobs(jobs, processes=args.jobs, label="learning", progress=ProgressLine)
    learnt = [n for n, e in zip(names, errors, strict=True) if e is None]
    exact = np.array([RunFolder(folder.run(n)).read_summary()["distance_m"] for n in learnt])
    curves = [RunFolder(folder.run(n)).read_metrics()["greedy_exact_m"] for n in learnt]
    lines = [
        f"{inputs['formation']} in {inputs['world']}, seed {inputs['settings']['seed']}: "
        f"{len(learnt)} candidates learnt to the end",
        "",
        "| screening generations | Spearman's rho | p | full run's best in the estimate's top 3 |",
        "|---|---|---|---|",
    ]
    best = learnt[int(np.argmax(exact))]
    for screen in args.screens:
        estimate = np.array([curve[:screen].max() for curve in curves])
        rho, p = spearmanr(estimate, exact)
        top = [learnt[i] for i in np.argsort(-estimate, kind="stable")[:3]]
        lines.append(f"| {screen} | {rho:.2f} | {p:.1g} | {'yes' if best in top else 'no'} |")
    lines += ["", "| candidate | " + " | ".join(f"after {s}" for s in args.screens) + " | full |"]
    lines.append("|---|" + "---|" * (len(args.screens) + 1))
    for name, curve, full in zip(learnt, curves, exact, strict=True):
        cells = " | ".join(f"{curve[:s].max():.3f}" for s in args.screens)
        lines.append(f"| {name} | {cells} | {full:.3f} |")
    text = "\n".join(lines) + "\n"
    (args.reform / "screening_correlation.md").write_text(text, encoding="utf-8")
    print(text)


if __name__ == "__main__":
    main()
