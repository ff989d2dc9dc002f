"""``qdsega.progress``: the clock, the ETA, the throttling, and the last line never lost."""

from __future__ import annotations

import io

import pytest

from qdsega.progress import ProgressFactory, ProgressLine, clock


class Clock:
    """A clock the test moves by hand (s)."""

    def __init__(self) -> None:
        self.now = 100.0

    def __call__(self) -> float:
        return self.now


def _line(stream: io.StringIO, clock_: Clock, total: int = 10, **options: float) -> ProgressLine:
    return ProgressLine("work", total, stream=stream, time_source=clock_, **options)


@pytest.mark.parametrize(
    ("seconds", "text"),
    [(0, "0:00"), (59.4, "0:59"), (59.6, "1:00"), (61, "1:01"), (3599, "59:59"),
     (3600, "1:00:00"), (3 * 3600 + 62, "3:01:02")],
)  # fmt: skip
def test_clock(seconds, text):
    assert clock(seconds) == text


def test_the_eta_is_the_rate_so_far_times_what_is_left():
    stream, now = io.StringIO(), Clock()
    line = _line(stream, now)
    now.now += 40
    line.update(4, "best 1.077 m")
    assert stream.getvalue() == "work 4/10: best 1.077 m, elapsed 0:40, ETA 1:00\n"
    now.now += 20
    line.update(5)  # throttled, but the time since the last line is 20 s
    assert stream.getvalue().splitlines()[-1] == "work 5/10: elapsed 1:00, ETA 1:00"


def test_work_done_before_the_line_is_left_out_of_the_rate():
    stream, now = io.StringIO(), Clock()
    line = _line(stream, now, initial=4)
    line.update(4)
    assert stream.getvalue() == "work 4/10: elapsed 0:00, ETA ?\n"
    now.now += 10
    line.update(6)  # 2 in 10 s: the 4 left take 20 s (not 6.7 s, as if all 6 took 10 s)
    assert stream.getvalue().splitlines()[-1] == "work 6/10: elapsed 0:10, ETA 0:20"


def test_lines_are_throttled_and_the_last_one_is_always_printed():
    stream, now = io.StringIO(), Clock()
    line = _line(stream, now, every_s=5.0)
    for done in range(1, 10):
        now.now += 1
        line.update(done)
    lines = stream.getvalue().splitlines()
    assert [text.split(":")[0] for text in lines] == ["work 1/10", "work 6/10"]
    now.now += 1
    line.update(10)  # done: printed at once, however soon
    assert stream.getvalue().splitlines()[-1] == "work 10/10: elapsed 0:10, ETA 0:00"
    line.close()  # nothing pending: nothing more
    assert len(stream.getvalue().splitlines()) == 3


def test_close_prints_an_update_the_throttle_held_back():
    stream, now = io.StringIO(), Clock()
    with _line(stream, now, total=600) as line:
        line.update(11, "best 0.100 m")
        now.now += 1
        line.update(594, "best 0.400 m")  # a search may stop short of its budget
        assert len(stream.getvalue().splitlines()) == 1
    last = stream.getvalue().splitlines()[-1]
    assert last == "work 594/600: best 0.400 m, elapsed 0:01, ETA 0:00"


def test_short_work_under_the_delay_prints_nothing():
    stream, now = io.StringIO(), Clock()
    quick = _line(stream, now, delay_s=5.0)
    now.now += 2
    quick.update(10)
    quick.close()
    assert stream.getvalue() == ""
    slow = _line(stream, now, delay_s=5.0)
    now.now += 3
    slow.update(2)
    now.now += 3
    slow.update(3)
    slow.close()
    assert stream.getvalue() == "work 3/10: elapsed 0:06, ETA 0:14\n"


def test_a_terminal_gets_a_bar_that_ends_cleanly():
    class Terminal(io.StringIO):
        def isatty(self) -> bool:
            return True

    stream = Terminal()
    with ProgressLine("runs", 3, stream=stream) as line:
        line.update(1, "last: ok")
        line.update(3)
    output = stream.getvalue()
    assert "runs 3/3" in output and "last: ok" in output and "elapsed" in output


def test_the_class_is_a_factory():
    factory: ProgressFactory = ProgressLine
    stream = io.StringIO()
    line = factory("x", 1, delay_s=0.0)
    line.stream = stream
    line.update(1)
    assert stream.getvalue().startswith("x 1/1: elapsed 0:00, ETA 0:00")
