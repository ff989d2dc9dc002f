"""The simulators a repertoire's archive can be filled in, each with its default budget, and
which one a body gets by default; apart from the build, so that the command line offers them
without loading it.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from qdsega.description import Formation

FILLS = {"pybullet": (2000, 128), "msm": (200_000, 2048)}
"""Each fill's default gaits played in its simulator and archive cells: PyBullet (exact physics)
plays a few thousand gaits in minutes, the MSM hundreds of thousands, and exact physics then
plays each of its elites once."""
RENAMED_FILLS = {"exact": "pybullet"}
"""Fill names before 0.2.0, still read (records) and taken (``--fill``, with a warning) until
0.3.0."""


def fill_name(name: str) -> str:
    """``name``, or what a name from before 0.2.0 is called now."""
    return RENAMED_FILLS.get(name, name)


def default_fill(formation: Formation) -> str:
    """The MSM for a body it models (legs on both sides), else PyBullet: on the shipped
    legged changes the MSM's archive held as good or better gaits for the changed body."""
    sides = {leg.side for leg in formation.legs}
    return "msm" if sides == {"left", "right"} else "pybullet"
