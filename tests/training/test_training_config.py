"""Presets exactly as section 4 gives them; YAML and flag overrides; bad input."""

from __future__ import annotations

import pytest
import yaml

from qdsega.errors import ConfigError
from qdsega.training.config import resolve_config
from qdsega.training.run import budget_overrides


def test_presets_are_the_papers():
    legged = resolve_config(preset="paper-legged").agent
    assert (legged.genetic.population, legged.genetic.generations) == (200, 200)
    assert (legged.genetic.crossover, legged.genetic.crossover_rate) == ("uniform", 0.2)
    assert legged.genetic.mutation_rate == 0.001 and legged.learning.trials == 10000
    snake = resolve_config(preset="paper-snake").agent
    assert (snake.genetic.population, snake.genetic.generations) == (30, 30)
    assert (snake.genetic.crossover, snake.genetic.crossover_rate) == ("one-point", 0.5)
    assert snake.genetic.mutation_rate == 0.02 and snake.learning.trials == 1000
    for agent in (legged, snake):
        assert (agent.learning.alpha, agent.learning.gamma) == (0.5, 0.9)
        assert agent.learning.temperature_scale == 150.0
        assert agent.learning.temperature_rate == 0.002


def test_yaml_then_flags_override(tmp_path):
    file = tmp_path / "o.yaml"
    file.write_text("seed: 3\nagent:\n  fitness: {k_f: 5}\n  learning: {trials: 50}\n")
    config = resolve_config(
        file=file, overrides=budget_overrides(generations=4, trials=7, seed=None)
    )
    assert config.seed == 3 and config.agent.fitness.k_f == 5.0
    assert config.agent.learning.trials == 7 and config.agent.genetic.generations == 4
    again = yaml.safe_load(yaml.safe_dump(config.to_dict()))
    assert resolve_config(overrides=again) == config


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("agent: {fitness: {kf: 1}}", "unknown key"),
        ("agent: {learning: {alpha: 2.0}}", "alpha"),
        ("seed: one", "integer"),
        ("sim: gazebo", "sim must be"),
    ],
)
def test_bad_overrides(tmp_path, text, message):
    file = tmp_path / "bad.yaml"
    file.write_text(text)
    with pytest.raises(ConfigError, match=message):
        resolve_config(file=file)


def test_the_default_preset_follows_the_body_and_the_world():
    from qdsega.description import load_formation
    from qdsega.training.config import default_preset

    snake, legged = (
        load_formation("assemblies/snake5.yaml"),
        load_formation("assemblies/hexapod.yaml"),
    )
    assert default_preset(legged, "msm") == "paper-legged"
    assert default_preset(legged, "memo") == default_preset(legged, "pybullet") == "memo-legged"
    assert default_preset(snake, "memo") == "paper-snake"
