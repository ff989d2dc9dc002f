"""The worlds a repertoire's archive can be filled in, and which one a body gets by default.

Kept apart from the build so that the command line can offer them without loading it.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from qdsega.description import Formation

FILLS = {"exact": (2000, 128), "msm": (50_000, 512)}
"""Each fill's default gaits played in its world and archive cells: exact physics plays a few
thousand gaits in minutes, the MSM tens of thousands in seconds."""


def default_fill(formation: Formation) -> str:
    """The MSM for a body it models (legs on both sides), else exact physics."""
    sides = {leg.side for leg in formation.legs}
    return "msm" if sides == {"left", "right"} else "exact"
