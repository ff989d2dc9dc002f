"""qdsega: modular hyper-redundant robots and the QDSEGA reinforcement learner."""

from importlib.metadata import version

from qdsega.locomotion import ENV_ID, TABLE_ENV_ID  # importing registers the Gymnasium envs

__version__ = version("qdsega")
"""The installed distribution's version: pyproject.toml is its one source."""

__all__ = ["ENV_ID", "TABLE_ENV_ID", "__version__"]
