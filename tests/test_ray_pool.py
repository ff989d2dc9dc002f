"""Ray actors as workers (``--ray local``): the same results as local processes, bit for bit."""

from __future__ import annotations

import numpy as np
import pytest

from qdsega.description import load_formation
from qdsega.locomotion.lower_agent import LowerAgentConfig
from qdsega.locomotion.memo import MeasuredTransitions

ray = pytest.importorskip("ray", reason="Ray is an optional extra: pip install 'qdsega[ray]'")


@pytest.fixture(scope="module")
def local_ray():
    from qdsega.ray_pool import LOCAL, connect

    yield connect(LOCAL)
    ray.shutdown()


def test_a_memo_table_measured_by_ray_actors_equals_the_local_one(local_ray):
    snake5 = load_formation("assemblies/snake5.yaml")
    postures = np.random.default_rng(1).integers(0, 9, size=(3, 4))
    local = MeasuredTransitions(formation=snake5, lower_agent=LowerAgentConfig(), workers=2)
    remote = MeasuredTransitions(
        formation=snake5, lower_agent=LowerAgentConfig(), workers=2, ray="local"
    )
    try:
        expected = local.transitions(postures, postures[::-1])
        measured = remote.transitions(postures, postures[::-1])
    finally:
        local.close()
        remote.close()
    assert remote.measured == 9
    for field in ("dx", "dy", "dtheta", "failed"):
        assert np.array_equal(getattr(measured, field), getattr(expected, field)), field
