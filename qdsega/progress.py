"""Progress of long work on the terminal: a bar on a TTY, a plain line every few seconds elsewhere.

Every step that may take more than a few seconds (the reference search, a sweep, a benchmark,
measuring a memo table) reports through a :class:`ProgressLine`. Library functions take an
optional :class:`ProgressFactory` (None: silent) and decide what they count; the commands pass
:class:`ProgressLine` itself, which writes to stderr. Off a terminal (a log file, a pipe, CI)
a line reads::

    reference search 132/600: best 0.412 m, elapsed 1:05, ETA 3:50

This module sits at the package's base: it imports nothing from qdsega.
"""

from __future__ import annotations

import shutil
import sys
import time
from collections.abc import Callable
from types import TracebackType
from typing import Any, Protocol, TextIO


def clock(seconds: float) -> str:
    """``h:mm:ss``, or ``m:ss`` under an hour (rounded to the second)."""
    minutes, secs = divmod(round(seconds), 60)
    hours, minutes = divmod(minutes, 60)
    return f"{hours}:{minutes:02d}:{secs:02d}" if hours else f"{minutes}:{secs:02d}"


class ProgressLine:
    """Progress of ``total`` items of work, written to ``stream`` (default: stderr).

    On a TTY it draws a tqdm bar. Elsewhere :meth:`update` prints
    ``LABEL done/total: facts, elapsed m:ss, ETA m:ss`` at most once per ``every_s`` seconds,
    and always when the work is done (``done >= total``) or on :meth:`close`, so the last
    state is never lost. Nothing at all shows for work shorter than ``delay_s`` seconds
    (to keep short batches quiet).

    Args:
        label: what is counted, first on the line.
        total: items in all (-).
        stream: where to write; default ``sys.stderr`` when the line is made.
        every_s: least time between two plain lines (s).
        delay_s: no output before this much time has passed since the line was made (s).
        initial: items already done before the line was made: shown, but left out of the
            rate the ETA assumes (-).
        time_source: the clock (s), for tests.
    """

    def __init__(
        self,
        label: str,
        total: int,
        *,
        stream: TextIO | None = None,
        every_s: float = 10.0,
        delay_s: float = 0.0,
        initial: int = 0,
        time_source: Callable[[], float] = time.monotonic,
    ) -> None:
        self.label = label
        self.total = total
        self.stream = stream if stream is not None else sys.stderr
        self.every_s = every_s
        self.delay_s = delay_s
        self.initial = initial
        self._now = time_source
        self._start = time_source()
        self._printed_at: float | None = None
        self._pending: tuple[int, str] | None = None  # the last update not printed yet
        self._bar: Any = None  # a tqdm bar, on a TTY
        if _is_tty(self.stream):
            from tqdm import tqdm  # only where a bar is drawn

            size = shutil.get_terminal_size()  # 80 x 24 where the terminal reports 0 x 0
            self._bar = tqdm(
                total=total,
                initial=initial,
                desc=label,
                bar_format="{desc} {n_fmt}/{total_fmt} |{bar:8}| {elapsed} elapsed, "
                "{remaining} left{postfix}",
                file=self.stream,
                delay=delay_s,
                leave=None,  # a bar below another one (memo under training) goes when done
                ncols=size.columns,
                nrows=size.lines,
            )

    def update(self, done: int, facts: str = "") -> None:
        """``done`` items of ``total`` are done; ``facts`` says more (e.g. the best so far)."""
        if self._bar is not None:
            if facts:
                self._bar.set_postfix_str(facts, refresh=False)
            self._bar.update(done - self._bar.n)
            return
        now = self._now()
        self._pending = (done, facts)
        if now - self._start < self.delay_s:
            return
        due = self._printed_at is None or now - self._printed_at >= self.every_s
        if due or done >= self.total:
            self._print(now)

    def line(self, done: int, facts: str, now: float) -> str:
        """The plain line for ``done`` items at time ``now``."""
        elapsed = now - self._start
        counted = done - self.initial
        if done >= self.total:
            eta = "0:00"
        elif counted > 0:
            eta = clock(elapsed / counted * (self.total - done))
        else:
            eta = "?"
        head = f"{self.label} {done}/{self.total}: "
        return f"{head}{facts + ', ' if facts else ''}elapsed {clock(elapsed)}, ETA {eta}"

    def close(self) -> None:
        """Print the last update if it has not been (after ``delay_s``); end the bar."""
        if self._bar is not None:
            self._bar.close()
            self._bar = None
            return
        now = self._now()
        if self._pending is not None and now - self._start >= self.delay_s:
            self._print(now)

    def __enter__(self) -> ProgressLine:
        return self

    def __exit__(
        self,
        kind: type[BaseException] | None,
        value: BaseException | None,
        traceback: TracebackType | None,
    ) -> None:
        self.close()

    def _print(self, now: float) -> None:
        assert self._pending is not None
        done, facts = self._pending
        print(self.line(done, facts, now), file=self.stream, flush=True)
        self._printed_at = now
        self._pending = None


class ProgressFactory(Protocol):
    """Makes the :class:`ProgressLine` of one piece of work (:class:`ProgressLine` is one)."""

    def __call__(
        self, label: str, total: int, *, delay_s: float = 0.0, initial: int = 0
    ) -> ProgressLine: ...


def _is_tty(stream: TextIO) -> bool:
    isatty = getattr(stream, "isatty", None)
    return bool(isatty and isatty())
