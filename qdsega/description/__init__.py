"""Descriptions: YAML unit and formation files read into validated dataclasses."""

from qdsega.description.formation import (
    ActuatedJoint,
    Formation,
    Friction,
    Leg,
    Light,
    PlacedUnit,
)
from qdsega.description.formation_reader import load_formation
from qdsega.description.shipped import (
    resolve_formation,
    resolve_world,
    shipped_formation_names,
    shipped_unit_names,
    shipped_world_names,
)
from qdsega.description.unit_type import Connector, JointSpec, UnitType, load_unit_type
from qdsega.description.world import World, load_world, named_world

__all__ = [
    "ActuatedJoint",
    "Connector",
    "Formation",
    "Friction",
    "JointSpec",
    "Leg",
    "Light",
    "PlacedUnit",
    "UnitType",
    "World",
    "load_formation",
    "load_unit_type",
    "load_world",
    "named_world",
    "resolve_formation",
    "resolve_world",
    "shipped_formation_names",
    "shipped_unit_names",
    "shipped_world_names",
]
