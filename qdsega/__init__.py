"""qdsega: modular hyper-redundant robots and the QDSEGA reinforcement learner."""

from importlib.resources import files
from pathlib import Path

import gymnasium

__version__ = "0.1.0"

ENV_ID = "qdsega/Locomotion-v0"
"""The Gymnasium id of :class:`qdsega.locomotion.env.LocomotionEnv`, registered on import (the
entry point is a string: PyBullet loads only when an env is made)."""

gymnasium.register(id=ENV_ID, entry_point="qdsega.locomotion.env:LocomotionEnv")

TABLE_ENV_ID = "qdsega/TableLocomotion-v0"
"""The Gymnasium id of :class:`qdsega.training.table_env.TableLocomotionEnv`: the same task in
a table world (the MSM or a memo table), for learners other than QDSEGA at table speed."""

gymnasium.register(id=TABLE_ENV_ID, entry_point="qdsega.training.table_env:TableLocomotionEnv")


def _data_folder(package: str) -> Path:
    """The folder of data package ``package``; installs are plain files, never zipped."""
    folder = files(package)
    if not isinstance(folder, Path):
        raise ImportError(f"{package} is not a folder on disk ({folder}); install qdsega unzipped")
    return folder


UNITS_DIR = _data_folder("qdsega.units")
"""Shipped unit types, one folder each: ``units/`` of the checkout (``qdsega/units`` installed)."""

ASSEMBLIES_DIR = _data_folder("qdsega.assemblies")
"""Shipped formation files: ``assemblies/`` of the checkout (``qdsega/assemblies`` installed)."""
