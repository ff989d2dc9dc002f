"""The resolved configuration of a training run: preset, then YAML file, then CLI flags.

A YAML override file mirrors :class:`TrainingConfig` (a run folder's ``config.yaml`` is one),
for example::

    preset: paper-snake
    sim: memo
    seed: 3
    workers: 2
    agent:
      learning: {trials: 2000}
      fitness: {k_f: 10.0}
    task: {trial_steps: 20}
    msm: {c_theta: 0.1}

``preset:`` picks the preset the other keys change (``--preset`` picks it over the file's);
every other key overrides the preset's value, and flags override the file.
Unknown keys and values of the wrong type are errors (:class:`qdsega.errors.ConfigError`).
"""

from __future__ import annotations

import dataclasses
import math
import types
import typing
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

from qdsega.agent.config import PRESETS, QDSEGAConfig
from qdsega.description import Formation, Light, World
from qdsega.errors import ConfigError, QdsegaError, RunFolderError
from qdsega.locomotion.lower_agent import LowerAgentConfig
from qdsega.locomotion.rules import ExactRules
from qdsega.msm import MSMParameters
from qdsega.simulation import PhysicsSettings
from qdsega.task import TaskConfig
from qdsega.training.run_folder import RunFolder
from qdsega.yaml_reader import KeyPath, YamlDocument, format_key_path, load_yaml

SIMULATORS = ("msm", "memo", "pybullet")
"""Worlds ``qdsega train`` can learn in (:mod:`qdsega.training.sims`)."""
SCREENING_GENERATIONS = 8
"""The screening budget: a body's own preset cut to this many generations, to rank many bodies
(``qdsega match``) or candidate formations (``qdsega reform``) before learning the best ones."""
DEFAULT_PRESET = "paper-legged"
"""The preset of a configuration that names none and knows no body (see
:func:`default_preset` for the rule a run applies)."""


@dataclass(frozen=True)
class TrainingConfig:
    """Everything a training run depends on.

    Attributes:
        preset: the preset the run started from (``paper-legged`` or ``paper-snake``).
        seed: seed of the run's only random generator.
        sim: the simulator: ``msm`` (the Minimal Simulation Model of section 4.1.2), ``memo``
            (PyBullet transitions measured once each) or ``pybullet`` (exact physics).
        light_bearing_deg: put the light at this bearing (deg, counter-clockwise from the
            initial heading), at the formation's distance; None keeps the formation's light.
        agent: the learner's hyperparameters.
        task: the task's rules: trial length, reward (eq. 17) and its distance unit, penalty,
            exterior states.
        msm: the Minimal Simulation Model's constants.
        lower_agent: how PyBullet executes postures and when that fails.
        physics: PyBullet engine settings.
        workers: processes measuring memo transitions in parallel (and running exact
            trials).
        ray: None for local processes; ``local`` (a Ray instance started on this machine) or
            a Ray cluster's address: memo transitions are measured by ``workers`` Ray actors
            there (:mod:`qdsega.workers.ray_cluster`), exact trials stay on local processes.
            What a run learns does not depend on it.
        ground_table: memo mode: correct the table with the moves that each generation's
            exact replay of its greedy policy went through (:mod:`qdsega.agent.grounding`).
        explore_trials: memo mode with ``ground_table``: trials of each generation's
            Q-table drawn at eq. (18)'s last temperature and replayed with exact physics,
            besides the greedy one, to ground the table where the learner may go next.
        optimism: memo mode with ``ground_table``: when positive, one more exact trial per
            generation, the greedy policy of a further learning phase on the table whose
            unobserved forward moves are the measured ones plus ``optimism`` times the RMS
            gap between measured and observed moves (an upper confidence bound), so that
            exact physics tries what the table may underrate; 0 for none (-). 1.0: it finds
            gaits the greedy policy then keeps, with less straying than 3.0
            (docs/algorithm.md).
        local_search: memo mode: neighbours of the best exact trial so far replayed with
            exact physics each generation, the best one's postures kept in the population
            (:class:`qdsega.agent.verification.Verification`); 0 for none (-). 10: it lifts the
            worst seeds most, for about twice the wall time (docs/algorithm.md).
        phase_moves: the share of local-search neighbours that shift one joint's commands one
            step in time instead of moving one level (:func:`qdsega.agent.genetic.vary_gait`),
            in [0, 1] (-). 0: every neighbour a level move (0.5 measured mixed;
            docs/algorithm.md).
        memo_spots: memo mode: how many places along the way to the light each move is
            measured from, the table keeping their mean move
            (:mod:`qdsega.locomotion.memo`); None: 1 (the origin) on a plane, level or tilted
            (:attr:`qdsega.description.World.is_plane`), else
            :data:`qdsega.training.sims.VARIED_GROUND_SPOTS`.
    """

    preset: str = DEFAULT_PRESET
    seed: int = 0
    sim: str = "msm"
    light_bearing_deg: float | None = None
    agent: QDSEGAConfig = field(default_factory=QDSEGAConfig)
    task: TaskConfig = field(default_factory=TaskConfig)
    msm: MSMParameters = field(default_factory=MSMParameters)
    lower_agent: LowerAgentConfig = field(default_factory=LowerAgentConfig)
    physics: PhysicsSettings = field(default_factory=PhysicsSettings)
    workers: int = 2
    ray: str | None = None
    ground_table: bool = True
    explore_trials: int = 4
    optimism: float = 1.0
    local_search: int = 10
    phase_moves: float = 0.0
    memo_spots: int | None = None

    def __post_init__(self) -> None:
        if self.workers < 1:
            raise ValueError(f"workers must be at least 1, got {self.workers}")
        if self.explore_trials < 0:
            raise ValueError(f"explore_trials must not be negative, got {self.explore_trials}")
        if self.local_search < 0:
            raise ValueError(f"local_search must not be negative, got {self.local_search}")
        if not 0.0 <= self.phase_moves <= 1.0:
            raise ValueError(f"phase_moves must be in [0, 1], got {self.phase_moves}")
        if self.memo_spots is not None and self.memo_spots < 1:
            raise ValueError(f"memo_spots must be at least 1, got {self.memo_spots}")
        if not (self.optimism >= 0 and math.isfinite(self.optimism)):
            raise ValueError(f"optimism must not be negative, got {self.optimism}")

    def to_dict(self) -> dict[str, Any]:
        """Plain types only (tuples become lists), for YAML."""
        return _plain(dataclasses.asdict(self))

    def rules(self, world: World | None = None) -> ExactRules:
        """What exact physics judges this run's trials by: its task, lower agent and physics,
        in ``world`` (default flat)."""
        return ExactRules(
            task=self.task,
            lower_agent=self.lower_agent,
            physics=self.physics,
            world=world or World(),
        )

    def with_light(self, formation: Formation) -> Formation:
        """``formation`` with its light moved to ``light_bearing_deg`` (at its distance), or
        unchanged when that is None."""
        if self.light_bearing_deg is None:
            return formation
        light = Light(formation.light.distance_m, math.radians(self.light_bearing_deg))
        return formation.with_light(light)


def default_preset(formation: Formation, sim: str) -> str:
    """The preset for ``formation`` in simulator ``sim`` when none is named (train, sweep and
    bench alike): ``paper-legged`` in the MSM, else ``memo-legged`` for a legged body and
    ``paper-snake`` for a legless one."""
    if sim == "msm":
        return "paper-legged"
    return "memo-legged" if formation.legs else "paper-snake"


def resolve_config(
    *,
    preset: str | None = None,
    file: Path | None = None,
    overrides: dict[str, Any] | None = None,
    formation: Formation | None = None,
) -> TrainingConfig:
    """A preset, updated by the YAML ``file``, then by ``overrides`` (same nesting).

    The preset is ``preset``, else the one ``overrides`` or else ``file`` names (key
    ``preset``), else :func:`default_preset` for ``formation`` in the simulator the layers
    name, else :data:`DEFAULT_PRESET`.

    Raises:
        ConfigError: unknown preset, unreadable file, unknown key or bad value (with the file's
            line where it has one).
    """
    document = None if file is None else load_yaml(Path(file), error_type=ConfigError)
    if document is not None and not isinstance(document.data, dict):
        raise document.error((), "expected a mapping of settings")
    layers = [(document.data if document else {}, document), (overrides or {}, None)]
    for layer, source in reversed(layers):
        if preset is None and "preset" in layer:
            preset = _convert(layer["preset"], str, ("preset",), source)
    if preset is None and formation is not None:
        sim = TrainingConfig.sim
        for layer, source in layers:
            if "sim" in layer:
                sim = _convert(layer["sim"], str, ("sim",), source)
        preset = default_preset(formation, sim)
    preset = preset or DEFAULT_PRESET
    if preset not in PRESETS:
        raise ConfigError(f"unknown preset {preset!r} (known: {', '.join(PRESETS)})")
    config = TrainingConfig(preset=preset, agent=PRESETS[preset].agent, task=PRESETS[preset].task)
    for layer, source in layers:
        config = _merge(config, {k: v for k, v in layer.items() if k != "preset"}, (), source)
    if config.sim not in SIMULATORS:
        raise ConfigError(f"sim must be one of {', '.join(SIMULATORS)}, got {config.sim!r}")
    return config


def read_run_config(run: Path) -> TrainingConfig:
    """The configuration a run folder was trained with (its ``config.yaml``).

    Raises:
        RunFolderError: no config.yaml, or one that is not a configuration.
    """
    file = run / RunFolder.CONFIG
    if not file.is_file():
        raise RunFolderError("not a run folder (no config.yaml)", file=run)
    try:
        data = load_yaml(file, error_type=RunFolderError).data
        if not isinstance(data, dict) or "preset" not in data:
            raise RunFolderError("config.yaml is not a configuration", file=file)
        return resolve_config(file=file)
    except QdsegaError as exc:
        raise RunFolderError(f"corrupt run folder ({exc})", file=run) from None


def _error(message: str, path: KeyPath, source: YamlDocument | None) -> ConfigError:
    """A configuration error at ``path``, with its file and line where it came from one."""
    if source is not None:
        return ConfigError(
            message, file=source.file, line=source.line(path), key_path=format_key_path(path)
        )
    return ConfigError(message, key_path=format_key_path(path) or None)


def _merge(instance: Any, data: Any, path: KeyPath, source: YamlDocument | None) -> Any:
    if not isinstance(data, dict):
        raise _error("expected a mapping", path, source)
    hints = typing.get_type_hints(type(instance))
    names = {f.name for f in dataclasses.fields(instance)}
    changes = {}
    for key, value in data.items():
        key_path = (*path, key)
        if key not in names:
            raise _error(f"unknown key (known: {', '.join(sorted(names))})", key_path, source)
        current = getattr(instance, key)
        if dataclasses.is_dataclass(current):
            changes[key] = _merge(current, value, key_path, source)
        else:
            changes[key] = _convert(value, hints[key], key_path, source)
    try:
        return replace(instance, **changes)
    except ValueError as exc:
        raise _error(str(exc), path, source) from None


def _convert(value: Any, hint: Any, path: KeyPath, source: YamlDocument | None) -> Any:
    origin, args = typing.get_origin(hint), typing.get_args(hint)
    if origin in (typing.Union, types.UnionType):
        if value is None and type(None) in args:
            return None
        hint = next(a for a in args if a is not type(None))
        origin, args = typing.get_origin(hint), typing.get_args(hint)
    if origin is tuple:
        if not isinstance(value, list | tuple):
            raise _error("expected a list", path, source)
        return tuple(_convert(v, args[0], (*path, i), source) for i, v in enumerate(value))
    if origin is typing.Literal:
        if value not in args:
            raise _error(f"expected one of {', '.join(map(str, args))}", path, source)
        return value
    if hint is bool:
        if not isinstance(value, bool):
            raise _error("expected true or false", path, source)
        return value
    if hint is int:
        if isinstance(value, bool) or not isinstance(value, int):
            raise _error("expected an integer", path, source)
        return value
    if hint is float:
        if isinstance(value, bool) or not isinstance(value, int | float):
            raise _error("expected a number", path, source)
        if not math.isfinite(value):
            raise _error(f"expected a finite number, got {value}", path, source)
        return float(value)
    if hint is str:
        if not isinstance(value, str):
            raise _error("expected text", path, source)
        return value
    raise _error(f"unsupported setting type {hint}", path, source)


def _plain(value: Any) -> Any:
    if isinstance(value, dict):
        return {k: _plain(v) for k, v in value.items()}
    if isinstance(value, list | tuple):
        return [_plain(v) for v in value]
    return value
