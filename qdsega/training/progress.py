"""Progress of a training run on the terminal: a bar on a TTY, plain log lines elsewhere."""

from __future__ import annotations

import shutil
import sys
from typing import Any, TextIO

from tqdm import tqdm

from qdsega.progress import clock
from qdsega.training.run import GenerationReport
from qdsega.training.sims import Failures


class ProgressDisplay:
    """A :class:`qdsega.training.run.Progress` that writes to ``stream``.

    On a terminal it draws a bar (generation, the greedy policy's distance with exact physics
    and as the learner's model predicted it, Q-table size, steps/s, the share of the verified
    trials' commands that failed and how, ETA); otherwise (a log file, a pipe, CI) it prints
    one line per generation with the same facts.
    """

    def __init__(self, stream: TextIO | None = None) -> None:
        self.stream = sys.stderr if stream is None else stream
        self.interactive = self.stream.isatty()
        self._bar: tqdm[Any] | None = None

    def start(self, *, completed: int, generations: int) -> None:
        if self.interactive:
            size = shutil.get_terminal_size()  # 80 x 24 where the terminal reports 0 x 0
            self._bar = tqdm(
                total=generations,
                initial=completed,
                desc="generation",
                bar_format="{desc} {n_fmt}/{total_fmt} |{bar:8}| {remaining} left{postfix}",
                file=self.stream,
                ncols=size.columns,
                nrows=size.lines,
            )

    def generation(self, report: GenerationReport, failed: Failures) -> None:
        facts = (
            f"exact {report.greedy_exact_m:.3f} m (predicted {report.greedy_distance_m:.3f} m), "
            f"Q-table {report.actions} actions "
            f"({report.q_entries} entries), {report.steps_per_s:,.0f} steps/s"
        )
        if failed.kinds:
            facts += f", {failed.share:.1%} of commands failed ({failed.most_common})"
        if self._bar is not None:
            self._bar.set_postfix_str(facts, refresh=False)
            self._bar.update(1)
            return
        left = report.generations - report.generation
        eta = report.session_s / report.session_generations * left
        print(
            f"generation {report.generation}/{report.generations}: {facts}, "
            f"elapsed {clock(report.elapsed_s)}, ETA {clock(eta)}",
            file=self.stream,
            flush=True,
        )

    def close(self) -> None:
        if self._bar is not None:
            self._bar.close()
            self._bar = None
