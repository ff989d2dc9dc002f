"""Assembly: a formation becomes a self-contained, validated URDF."""

from qdsega.assembly.assembler import AssembledRobot, assemble, write_assembly

__all__ = ["AssembledRobot", "assemble", "write_assembly"]
