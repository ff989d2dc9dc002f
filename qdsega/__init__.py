"""qdsega: modular hyper-redundant robots and the QDSEGA reinforcement learner."""

from qdsega.locomotion import ENV_ID, TABLE_ENV_ID  # importing registers the Gymnasium envs

__version__ = "0.1.0"

__all__ = ["ENV_ID", "TABLE_ENV_ID", "__version__"]
