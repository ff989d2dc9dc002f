"""The progress display: a bar on a terminal, one plain line per generation elsewhere."""

from __future__ import annotations

import io

from qdsega.training.progress import ProgressDisplay
from qdsega.training.run import GenerationReport
from qdsega.training.sims import Failures


class _Terminal(io.StringIO):
    def isatty(self) -> bool:
        return True


def _report(generation: int) -> GenerationReport:
    return GenerationReport(
        generation=generation,
        generations=4,
        greedy_distance_m=0.25 * generation,
        greedy_exact_m=0.2 * generation,
        actions=12,
        q_entries=480,
        steps_per_s=1500.0,
        elapsed_s=30.0 * generation,
        session_s=30.0 * (generation - 1),
        session_generations=generation - 1,
    )


def test_a_terminal_gets_a_bar_that_starts_where_a_resumed_run_stands(monkeypatch):
    monkeypatch.setenv("COLUMNS", "150")
    stream = _Terminal()
    display = ProgressDisplay(stream)
    display.start(completed=1, generations=4)
    display.generation(_report(2), Failures())
    display.close()
    text = stream.getvalue()
    assert "generation 1/4" in text and "generation 2/4" in text and "\r" in text
    assert "left, exact 0.400 m (predicted 0.500 m), Q-table 12 actions" in text


def test_a_log_gets_lines_with_elapsed_time_and_eta():
    stream = io.StringIO()
    display = ProgressDisplay(stream)
    display.start(completed=1, generations=4)
    display.generation(_report(2), Failures())
    display.close()
    assert stream.getvalue() == (
        "generation 2/4: exact 0.400 m (predicted 0.500 m), Q-table 12 actions (480 entries), "
        "1,500 steps/s, elapsed 1:00, ETA 1:00\n"
    )


def test_failed_commands_are_counted_and_named():
    stream = io.StringIO()
    display = ProgressDisplay(stream)
    display.start(completed=1, generations=4)
    failed = Failures(commands=8, trials=5, kinds={"trunk touched the ground": 2})
    display.generation(_report(2), failed)
    assert "1,500 steps/s, 25.0% of commands failed (trunk touched the ground), elapsed" in (
        stream.getvalue()
    )
