"""``qdsega train``'s configuration: the preset, then ``--config FILE``, then the flags."""

from __future__ import annotations

import pytest

from qdsega.cli import build_parser
from qdsega.commands.train import run_config
from qdsega.errors import ConfigError

EVERY_KEY = """\
preset: paper-snake
sim: memo
seed: 3
workers: 1
light_bearing_deg: 30.0
ray: local
agent:
  genetic: {generations: 4, population: 12}
  learning: {trials: 50}
"""


def _config(tmp_path, text: str | None, *flags: str):
    args = ["train", "snake5", *flags]
    if text is not None:
        file = tmp_path / "settings.yaml"
        file.write_text(text)
        args += ["--config", str(file)]
    return run_config(build_parser().parse_args(args))


def test_without_file_or_flags_the_defaults():
    config = run_config(build_parser().parse_args(["train", "snake5"]))
    assert (config.preset, config.sim, config.seed, config.workers) == ("paper-legged", "msm", 0, 2)
    assert (
        config.light_bearing_deg is None
        and config.ray is None
        and config.agent.genetic.population == 200
    )


@pytest.mark.parametrize(
    ("formation", "sim", "preset"),
    [
        ("snake5", "memo", "paper-snake"),
        ("quadruped", "memo", "memo-legged"),
        ("quadruped", "msm", "paper-legged"),
        ("snake5", "pybullet", "paper-snake"),
    ],
)
def test_without_a_preset_the_body_and_the_simulator_choose_it(formation, sim, preset):
    args = build_parser().parse_args(["train", formation, "--sim", sim])
    assert run_config(args).preset == preset


def test_the_file_sets_every_key_a_flag_sets(tmp_path):
    config = _config(tmp_path, EVERY_KEY)
    assert (config.preset, config.sim, config.seed, config.workers) == ("paper-snake", "memo", 3, 1)
    assert config.light_bearing_deg == 30.0 and config.ray == "local"
    assert (config.agent.genetic.generations, config.agent.learning.trials) == (4, 50)
    assert config.agent.genetic.population == 12  # the file over the preset's 30
    assert config.agent.genetic.crossover == "one-point"  # the file's preset: paper-snake's


def test_flags_override_the_file(tmp_path):
    config = _config(
        tmp_path, EVERY_KEY,
        "--preset", "memo-legged", "--sim", "pybullet", "--seed", "9", "--workers", "3",
        "--light-bearing-deg", "-45", "--generations", "2", "--trials", "7", "--ray", "ray://h:1",
    )  # fmt: skip
    assert (config.preset, config.sim, config.seed, config.workers) == (
        "memo-legged",
        "pybullet",
        9,
        3,
    )
    assert config.light_bearing_deg == -45.0 and config.ray == "ray://h:1"
    assert (config.agent.genetic.generations, config.agent.learning.trials) == (2, 7)
    assert config.agent.genetic.population == 12  # still the file's: no flag sets it
    assert config.agent.genetic.crossover == "uniform"  # memo-legged's, as --preset says


def test_a_flag_left_out_keeps_the_files_value(tmp_path):
    config = _config(tmp_path, EVERY_KEY, "--seed", "5")
    assert (config.seed, config.sim, config.workers) == (5, "memo", 1)


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("preset: 3\n", "settings.yaml:1: preset: expected text"),
        ("preset: fastest\n", "unknown preset 'fastest'"),
        ("- sim: memo\n", "expected a mapping"),
    ],
)
def test_a_bad_file_is_one_clear_error(tmp_path, text, message):
    with pytest.raises(ConfigError, match=message):
        _config(tmp_path, text)
