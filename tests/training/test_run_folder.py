"""What a run folder says of itself: when a run first reached a distance."""

import numpy as np

from qdsega.training.run_folder import METRIC_COLUMNS, RunFolder


def _folder(tmp_path, greedy_exact_m):
    folder = RunFolder(tmp_path)
    rows = np.zeros((len(greedy_exact_m), len(METRIC_COLUMNS)))
    rows[:, METRIC_COLUMNS.index("generation")] = np.arange(1, len(greedy_exact_m) + 1)
    rows[:, METRIC_COLUMNS.index("greedy_exact_m")] = greedy_exact_m
    rows[:, METRIC_COLUMNS.index("sim_steps")] = 100 * np.arange(1, len(greedy_exact_m) + 1)
    folder.write_metrics(rows)
    return folder


def test_reached_is_the_first_generation_at_the_distance(tmp_path):
    folder = _folder(tmp_path, [0.2, 0.9, 0.5, 1.1])
    assert folder.reached(0.8) == (2, 200)
    assert folder.reached(1.1) == (4, 400)
    assert folder.reached(1.2) == (None, None)


def test_a_warm_start_that_already_walks_far_enough_reached_it_at_generation_0(tmp_path):
    folder = _folder(tmp_path, [1.0, 1.2])
    folder.write_json(folder.WARM_START, {"handed_on_m": 1.05, "handed_on_steps": 30})
    assert folder.reached(1.0) == (0, 30)
    assert folder.reached(1.1) == (2, 200)  # the handed-on path fell short: learning did it
