"""The worlds a repertoire's archive can be filled in, each with its default budget, and which
one a body gets by default; apart from the build, so that the command line offers them without
loading it.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from qdsega.description import Formation

FILLS = {"exact": (2000, 128), "msm": (200_000, 2048)}
"""Each fill's default gaits played in its world and archive cells: exact physics plays a few
thousand gaits in minutes, the MSM hundreds of thousands, and exact physics then plays each of
its elites once."""


def default_fill(formation: Formation) -> str:
    """The MSM for a body it models (legs on both sides), else exact physics: on the shipped
    legged changes the MSM's archive held as good or better gaits for the changed body."""
    sides = {leg.side for leg in formation.legs}
    return "msm" if sides == {"left", "right"} else "exact"
