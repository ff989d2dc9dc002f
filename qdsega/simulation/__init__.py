"""Simulation: assembled formations in PyBullet.

Only :mod:`qdsega.simulation.bullet` imports pybullet (import ``BulletSimulation`` from there);
this package itself stays light so that configurations can name :class:`PhysicsSettings`
without starting the engine.
"""

from qdsega.simulation.settings import PhysicsSettings

__all__ = ["PhysicsSettings"]
