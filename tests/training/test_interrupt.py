import os
import signal
import time

import pytest

from qdsega.training.interrupt import InterruptWatch


def test_sigint_is_remembered_and_still_raises_keyboard_interrupt():
    before = signal.getsignal(signal.SIGINT)
    with InterruptWatch() as watch:
        assert not watch.interrupted
        with pytest.raises(KeyboardInterrupt):
            os.kill(os.getpid(), signal.SIGINT)
            time.sleep(5)  # not reached: the handler raises first, or interrupts the sleep
        assert watch.interrupted
    assert signal.getsignal(signal.SIGINT) is before


def test_without_sigint_nothing_is_remembered():
    with InterruptWatch() as watch:
        pass
    assert not watch.interrupted
