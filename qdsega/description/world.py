"""Worlds: the ground a body walks on, what stands on it, and the light, read from YAML.

A world is laid out in the frame a trial starts in: the body starts at the origin heading +x,
so stairs, a corridor and a tunnel run along +x. Every number is bounded as it is read and
every mistake names the file, the line and the key (the reader formations use). A world
that names no light leaves the formation's.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

from qdsega.description.formation import Formation, Light
from qdsega.description.formation_reader import read_light
from qdsega.description.shipped import resolve_world
from qdsega.errors import WorldError
from qdsega.yaml_reader import Interval, KeyPath, Reader, load_yaml

FRICTION = Interval(0.0, 10.0, open_low=True)
"""The ground's lateral friction coefficient (-)."""
SLOPE_DEG = Interval(-30.0, 30.0)
"""How steeply the ground rises toward ``toward_deg`` (deg)."""
BEARING_DEG = Interval(-360.0, 360.0)
"""Directions in the world, counter-clockwise from +x (deg)."""
HEIGHT_M = Interval(0.0, 1.0, open_low=True)
"""Heights of rough ground, a step's rise (m)."""
LENGTH_M = Interval(0.0, 100.0, open_low=True)
"""Lengths, widths and sizes in the world (m)."""
POSITION_M = Interval(-100.0, 100.0)
"""Positions in the world (m)."""
CELL_M = 0.05
"""Rough ground's heightfield cell (m): fine enough that a body does not sink into it."""
MAX_CELLS = 512
"""Heightfield cells along a side: rough ground spans at most ``MAX_CELLS * CELL_M`` m."""
MAX_BOXES = 256
"""Boxes (obstacles) in one world."""
MAX_STEPS = 100
"""Steps of one staircase."""

_TOP_KEYS = ("name",)
_TOP_OPTIONAL = ("description", "ground", "stairs", "boxes", "corridor", "ceiling", "light")


@dataclass(frozen=True)
class Rough:
    """Rough ground: a heightfield of smooth random bumps.

    Attributes:
        amplitude_m: the highest bump above the lowest dip (m).
        feature_m: the bumps' typical width (m).
        size_m: the side of the square of rough ground, centred ahead of the start (m).
        seed: the bumps' random seed.
    """

    amplitude_m: float
    feature_m: float
    size_m: float
    seed: int


@dataclass(frozen=True)
class Stairs:
    """Steps up along +x: ``count`` steps of ``rise_m`` each ``run_m`` deep, from ``from_m``,
    ``width_m`` wide."""

    from_m: float
    rise_m: float
    run_m: float
    count: int
    width_m: float


@dataclass(frozen=True)
class Box:
    """A fixed box standing on the ground (an obstacle): its centre (m), size (m) and yaw
    (rad)."""

    xyz_m: tuple[float, float, float]
    size_m: tuple[float, float, float]
    yaw_rad: float


def _box_key(box: Box, *, mirror: bool = False) -> tuple[float, ...]:
    """A box's place, size and yaw (modulo a half turn, which leaves a box as it is), rounded;
    with ``mirror``, those of its mirror image across y = 0."""
    x, y, z = box.xyz_m
    yaw = -box.yaw_rad if mirror else box.yaw_rad
    turn = round(math.degrees(yaw) % 180.0, 6) % 180.0
    return (round(x, 9), round(-y if mirror else y, 9), round(z, 9), *box.size_m, turn)


@dataclass(frozen=True)
class Corridor:
    """Two walls along +x, ``width_m`` apart, from behind the start to ``length_m``."""

    width_m: float
    length_m: float
    height_m: float


@dataclass(frozen=True)
class Ceiling:
    """A low roof (a tunnel) ``height_m`` above the ground from ``from_m`` to ``to_m`` along
    +x, ``width_m`` wide."""

    height_m: float
    from_m: float
    to_m: float
    width_m: float


@dataclass(frozen=True)
class World:
    """Where a body walks.

    Attributes:
        name: the world's name.
        description: one line on it.
        file: the YAML it was read from (None for the flat default).
        friction: the ground's lateral friction coefficient (-).
        slope_rad: how steeply the ground rises toward ``slope_toward_rad`` (rad).
        slope_toward_rad: that direction, counter-clockwise from +x (rad).
        rough: rough ground, or None.
        stairs: a staircase, or None.
        boxes: obstacles.
        corridor: walls on both sides, or None.
        ceiling: a roof, or None.
        light: the light, or None to keep the formation's.
    """

    name: str = "flat"
    description: str = "a flat plane"
    file: Path | None = None
    friction: float = 1.0
    slope_rad: float = 0.0
    slope_toward_rad: float = 0.0
    rough: Rough | None = None
    stairs: Stairs | None = None
    boxes: tuple[Box, ...] = ()
    corridor: Corridor | None = None
    ceiling: Ceiling | None = None
    light: Light | None = None

    @property
    def is_flat(self) -> bool:
        """A plane of friction 1 and nothing on it: the world every formation had before
        worlds existed (its light may differ)."""
        plain = World(name=self.name, description=self.description, file=self.file)
        return self == plain.with_light(self.light)

    @property
    def is_plane(self) -> bool:
        """A plane, level or tilted, with nothing on it: a move there does not depend on where
        the body stands (on a slope it may depend on which way the body faces)."""
        return self == replace(self, rough=None, stairs=None, boxes=(), corridor=None, ceiling=None)

    @property
    def is_uniform(self) -> bool:
        """A level plane with nothing on it, whatever its friction: a move there depends on
        neither where the body stands nor which way it faces."""
        return self.slope_rad == 0 and self.is_plane

    @property
    def is_mirror_symmetric(self) -> bool:
        """The world is its own mirror image across the start heading's vertical plane (y ->
        -y): no rough ground, a slope along the heading if any, every box with its mirror
        image, and a light (if it has one) straight ahead or behind. A body and its mirror
        image walk alike here, given a light ahead or behind."""
        along = self.slope_rad == 0 or abs(math.sin(self.slope_toward_rad)) < 1e-9
        light = self.light is None or abs(math.sin(self.light.bearing_rad)) < 1e-9
        boxes = {_box_key(box) for box in self.boxes}
        mirrored = all(_box_key(box, mirror=True) in boxes for box in self.boxes)
        return self.rough is None and along and light and mirrored

    def lights(self, formation: Formation) -> Formation:
        """``formation`` with this world's light, where the world has one."""
        return formation if self.light is None else formation.with_light(self.light)

    def with_light(self, light: Light | None) -> World:
        return World(**{**self.__dict__, "light": light})


def corridor_walls(corridor: Corridor) -> tuple[Box, Box]:
    """The corridor's two walls as boxes (their centres' heights above z = 0): 5 cm thick,
    from 1 m behind the start to ``length_m``."""
    thickness, length = 0.05, corridor.length_m + 1.0
    x, z = corridor.length_m - length / 2, corridor.height_m / 2
    size = (length, thickness, corridor.height_m)
    y = corridor.width_m / 2 + thickness / 2
    return (Box((x, -y, z), size, 0.0), Box((x, y, z), size, 0.0))


def roof_box(ceiling: Ceiling) -> Box:
    """A roof as a slab 5 cm thick (its centre's height above z = 0), from ``from_m`` to
    ``to_m``."""
    thickness = 0.05
    x = (ceiling.from_m + ceiling.to_m) / 2
    size = (ceiling.to_m - ceiling.from_m, ceiling.width_m, thickness)
    return Box((x, 0.0, ceiling.height_m + thickness / 2), size, 0.0)


def standing_boxes(world: World, *, roof: bool = False) -> tuple[Box, ...]:
    """What stands on ``world``'s ground for a body to go around: its boxes and walls (steps and
    rough ground are climbed). A roof is overhead; with ``roof`` it is in the way as well, for
    a body too tall to go under it."""
    walls = () if world.corridor is None else corridor_walls(world.corridor)
    above = () if world.ceiling is None or not roof else (roof_box(world.ceiling),)
    return world.boxes + walls + above


def load_world(file: Path | str) -> World:
    """Read and validate a world file.

    Raises:
        WorldError: one line naming the file, the line, the key path and what is wrong.
    """
    file = Path(file)
    reader = Reader(load_yaml(file, error_type=WorldError))
    top = reader.mapping((), reader.document.data, required=_TOP_KEYS, optional=_TOP_OPTIONAL)
    name = reader.text(("name",), top["name"])
    ground = reader.mapping(
        ("ground",), top.get("ground", {}), optional=("friction", "slope", "rough")
    )
    slope = _slope(reader, ground.get("slope"))
    rough = _rough(reader, ground.get("rough"))
    if rough is not None and slope[0] != 0.0:
        raise reader.error(("ground", "rough"), "rough ground on a slope is not supported")
    boxes = reader.sequence(("boxes",), top.get("boxes", []))
    if len(boxes) > MAX_BOXES:
        raise reader.error(("boxes",), f"at most {MAX_BOXES} boxes, got {len(boxes)}")
    return World(
        name=name,
        description=reader.text(("description",), top.get("description", name)),
        file=file,
        friction=reader.number(("ground", "friction"), ground.get("friction", 1.0), FRICTION),
        slope_rad=slope[0],
        slope_toward_rad=slope[1],
        rough=rough,
        stairs=_stairs(reader, top.get("stairs")),
        boxes=tuple(_box(reader, ("boxes", i), raw) for i, raw in enumerate(boxes)),
        corridor=_corridor(reader, top.get("corridor")),
        ceiling=_ceiling(reader, top.get("ceiling")),
        light=None if "light" not in top else read_light(reader, ("light",), top["light"]),
    )


def named_world(argument: str | Path) -> World:
    """The world a command-line argument means: a file, or a shipped world's name
    (:func:`qdsega.description.shipped.resolve_world`), read.

    Raises:
        WorldError: no such shipped world, or a file that does not read as a world.
    """
    return load_world(resolve_world(argument))


def _slope(reader: Reader, value: Any) -> tuple[float, float]:
    if value is None:
        return 0.0, 0.0
    path: KeyPath = ("ground", "slope")
    raw = reader.mapping(path, value, required=("angle_deg",), optional=("toward_deg",))
    angle = reader.number((*path, "angle_deg"), raw["angle_deg"], SLOPE_DEG)
    toward = reader.number((*path, "toward_deg"), raw.get("toward_deg", 0.0), BEARING_DEG)
    return math.radians(angle), math.radians(toward)


def _rough(reader: Reader, value: Any) -> Rough | None:
    if value is None:
        return None
    path: KeyPath = ("ground", "rough")
    raw = reader.mapping(
        path, value, required=("amplitude_m", "feature_m"), optional=("size_m", "seed")
    )
    size = reader.number((*path, "size_m"), raw.get("size_m", 8.0), LENGTH_M)
    if size / CELL_M > MAX_CELLS:
        limit = MAX_CELLS * CELL_M
        raise reader.error((*path, "size_m"), f"heightfield too large: at most {limit:g} m")
    feature = reader.number((*path, "feature_m"), raw["feature_m"], LENGTH_M)
    if feature < 2 * CELL_M:
        raise reader.error((*path, "feature_m"), f"must be at least {2 * CELL_M:g} m")
    return Rough(
        amplitude_m=reader.number((*path, "amplitude_m"), raw["amplitude_m"], HEIGHT_M),
        feature_m=feature,
        size_m=size,
        seed=reader.integer((*path, "seed"), raw.get("seed", 0), Interval(0, 2**31 - 1)),
    )


def _stairs(reader: Reader, value: Any) -> Stairs | None:
    if value is None:
        return None
    path: KeyPath = ("stairs",)
    keys = ("from_m", "rise_m", "run_m", "count")
    raw = reader.mapping(path, value, required=keys, optional=("width_m",))
    return Stairs(
        from_m=reader.number((*path, "from_m"), raw["from_m"], POSITION_M),
        rise_m=reader.number((*path, "rise_m"), raw["rise_m"], HEIGHT_M),
        run_m=reader.number((*path, "run_m"), raw["run_m"], LENGTH_M),
        count=reader.integer((*path, "count"), raw["count"], Interval(1, MAX_STEPS)),
        width_m=reader.number((*path, "width_m"), raw.get("width_m", 4.0), LENGTH_M),
    )


def _box(reader: Reader, path: KeyPath, value: Any) -> Box:
    raw = reader.mapping(path, value, required=("xyz_m", "size_m"), optional=("yaw_deg",))
    return Box(
        xyz_m=reader.triple((*path, "xyz_m"), raw["xyz_m"], POSITION_M),
        size_m=reader.triple((*path, "size_m"), raw["size_m"], LENGTH_M),
        yaw_rad=math.radians(
            reader.number((*path, "yaw_deg"), raw.get("yaw_deg", 0.0), BEARING_DEG)
        ),
    )


def _corridor(reader: Reader, value: Any) -> Corridor | None:
    if value is None:
        return None
    path: KeyPath = ("corridor",)
    raw = reader.mapping(path, value, required=("width_m",), optional=("length_m", "height_m"))
    return Corridor(
        width_m=reader.number((*path, "width_m"), raw["width_m"], LENGTH_M),
        length_m=reader.number((*path, "length_m"), raw.get("length_m", 20.0), LENGTH_M),
        height_m=reader.number((*path, "height_m"), raw.get("height_m", 0.3), LENGTH_M),
    )


def _ceiling(reader: Reader, value: Any) -> Ceiling | None:
    if value is None:
        return None
    path: KeyPath = ("ceiling",)
    raw = reader.mapping(
        path, value, required=("height_m",), optional=("from_m", "to_m", "width_m")
    )
    ceiling = Ceiling(
        height_m=reader.number((*path, "height_m"), raw["height_m"], HEIGHT_M),
        from_m=reader.number((*path, "from_m"), raw.get("from_m", 0.5), POSITION_M),
        to_m=reader.number((*path, "to_m"), raw.get("to_m", 20.0), POSITION_M),
        width_m=reader.number((*path, "width_m"), raw.get("width_m", 4.0), LENGTH_M),
    )
    if ceiling.to_m <= ceiling.from_m:
        raise reader.error((*path, "to_m"), "must be beyond from_m")
    return ceiling
