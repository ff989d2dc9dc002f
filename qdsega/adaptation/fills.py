"""The worlds a repertoire's archive can be filled in (the first is the default), each with
its default budget; apart from the build, so that the command line offers them without
loading it.
"""

FILLS = {"exact": (2000, 128), "msm": (50_000, 512)}
"""Each fill's default gaits played in its world and archive cells: exact physics plays a few
thousand gaits in minutes, the MSM tens of thousands in seconds."""
