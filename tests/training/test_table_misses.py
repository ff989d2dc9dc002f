"""A memo run says while it trains when its table keeps mispredicting exact physics, and from
then on searches in exact physics."""

from __future__ import annotations

import numpy as np

from qdsega.training.config import TrainingConfig
from qdsega.training.run import MISSES_TO_WARN, _search_size, _unheld, table_misses, unheld_since
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
    line = _unheld(metrics, TrainingConfig(local_search=10, exact_search=40))
    assert line.startswith(f"generations 2-{MISSES_TO_WARN + 1}: ")
    assert "+96%, +96%, +96%" in line and "\n" not in line
    assert line.endswith("and learns in it: 40 local-search trials a generation from now on")
    assert "learns in it" not in _unheld(metrics, TrainingConfig(exact_search=0))


def test_once_the_table_has_not_held_the_search_grows_and_stays_grown():
    config = TrainingConfig(local_search=10, exact_search=40)
    held = _metrics([(1.0, 1.0), (1.5, 1.0), (1.5, 1.0)])
    assert unheld_since(held) is None and _search_size(config, held) == 10
    unheld = _metrics([(1.0, 1.0), *[(1.5, 1.0)] * MISSES_TO_WARN, (1.0, 1.0)])
    assert unheld_since(unheld) == MISSES_TO_WARN + 1  # after generation 4, held again at 5
    assert _search_size(config, unheld) == 40
    assert _search_size(TrainingConfig(local_search=10, exact_search=0), unheld) == 10
