"""Ctrl-C during training, recognised whatever code it lands in.

Python raises ``KeyboardInterrupt`` wherever the interpreter happens to be when SIGINT
arrives. Inside a library's C code that calls back into Python the exception can come out as
another one: numpy 2.x, interrupted while comparing the structured rows of
``np.unique(..., axis=0)``, raises ``TypeError: Cannot compare structured arrays ...``
(seen once in the Ctrl-C test). :class:`InterruptWatch` remembers that SIGINT arrived, so the
training loop can treat whatever exception follows as the interrupt it is.
"""

from __future__ import annotations

import signal
import threading
from types import FrameType, TracebackType
from typing import Any


class InterruptWatch:
    """While active (a ``with`` block in the main thread), SIGINT sets :attr:`interrupted`
    and then raises ``KeyboardInterrupt`` as Python's default handler does."""

    def __init__(self) -> None:
        self.interrupted = False
        self._previous: Any = None
        self._installed = False

    def __enter__(self) -> InterruptWatch:
        if threading.current_thread() is threading.main_thread():
            self._previous = signal.signal(signal.SIGINT, self._handle)
            self._installed = True
        return self

    def __exit__(
        self,
        kind: type[BaseException] | None,
        value: BaseException | None,
        traceback: TracebackType | None,
    ) -> None:
        if self._installed:
            signal.signal(signal.SIGINT, self._previous)
            self._installed = False

    def _handle(self, signum: int, frame: FrameType | None) -> None:
        self.interrupted = True
        raise KeyboardInterrupt
