"""Simulation: assembled formations in PyBullet (the only package that imports pybullet)."""

from qdsega.simulation.bullet import BulletSimulation
from qdsega.simulation.settings import PhysicsSettings

__all__ = ["BulletSimulation", "PhysicsSettings"]
