"""Small leg layouts for MSM tests."""

from __future__ import annotations

from collections.abc import Callable

import pytest

from qdsega.msm import LegLayout


def _layout(per_side: int) -> LegLayout:
    """Legs L1.., then R1..; leg k uses joints 2k (swing) and 2k + 1 (lift)."""
    n = 2 * per_side
    names = [f"L{i + 1}" for i in range(per_side)] + [f"R{i + 1}" for i in range(per_side)]
    return LegLayout(
        n_joints=2 * n,
        swing=tuple(range(0, 2 * n, 2)),
        lift=tuple(range(1, 2 * n, 2)),
        right=tuple([False] * per_side + [True] * per_side),
        names=tuple(names),
    )


@pytest.fixture
def layout() -> Callable[[int], LegLayout]:
    """``layout(per_side)``: a body with that many legs on each side."""
    return _layout
