"""qdsega: modular hyper-redundant robots and the QDSEGA reinforcement learner."""

from pathlib import Path

__version__ = "0.1.0"

PROJECT_ROOT = Path(__file__).resolve().parent.parent
"""The checkout's root folder (holds units/ and assemblies/)."""

UNITS_DIR = PROJECT_ROOT / "units"
"""Shipped unit types, one folder each."""

ASSEMBLIES_DIR = PROJECT_ROOT / "assemblies"
"""Shipped formation files."""
