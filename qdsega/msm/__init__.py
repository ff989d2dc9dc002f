"""The Minimal Simulation Model of a legged robot (section 4.1.2) and its optimum."""

from qdsega.msm.legs import LEG_STATES, LegLayout
from qdsega.msm.model import MinimalSimulationModel, MSMParameters, side_force
from qdsega.msm.optimum import Optimum, msm_optimum

__all__ = [
    "LEG_STATES",
    "LegLayout",
    "MSMParameters",
    "MinimalSimulationModel",
    "Optimum",
    "msm_optimum",
    "side_force",
]
