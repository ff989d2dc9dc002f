"""A memo run says while it trains when its table keeps mispredicting exact physics."""

from __future__ import annotations

import numpy as np

from qdsega.training.run import MISSES_TO_WARN, _unheld, table_misses
from qdsega.training.run_folder import METRIC_COLUMNS


def _metrics(pairs: list[tuple[float, float]]) -> np.ndarray:
    """Rows of ``metrics.csv`` with (predicted, exact) greedy distances, generations 1..n."""
    rows = np.zeros((len(pairs), len(METRIC_COLUMNS)))
    rows[:, 0] = np.arange(1, len(pairs) + 1)
    rows[:, METRIC_COLUMNS.index("greedy_distance_m")] = [p for p, _ in pairs]
    rows[:, METRIC_COLUMNS.index("greedy_exact_m")] = [e for _, e in pairs]
    return rows


def test_misses_count_the_last_generations_in_a_row_beyond_the_tolerance():
    assert table_misses(_metrics([])) == 0
    assert table_misses(_metrics([(1.0, 0.5), (1.05, 1.0)])) == 0  # the last one held (+5 %)
    assert table_misses(_metrics([(1.05, 1.0), (1.0, 0.5), (0.2, 0.4)])) == 2
    assert table_misses(_metrics([(1.0, 0.5), (0.3, 0.0)])) == 0  # nothing to compare with


def test_the_warning_names_the_generations_and_their_errors():
    metrics = _metrics([(1.0, 1.0), *[(1.96, 1.0)] * MISSES_TO_WARN])
    assert table_misses(metrics) == MISSES_TO_WARN
    line = _unheld(metrics)
    assert line.startswith(f"generations 2-{MISSES_TO_WARN + 1}: ")
    assert "+96%, +96%, +96%" in line and "\n" not in line
