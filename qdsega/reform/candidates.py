"""Candidate bodies: what a robot's units can become, one move at a time or as a whole shape.

The moves tried are those a legged robot is re-formed by: a leg, or a trunk unit with what
hangs from it, goes to a free connector of the trunk, is set aside, or comes from the spares
(:func:`moves_from`). A body that is all trunk, such as a snake, moves any unit so. Two whole
shapes are tried as well, however many moves away they are (:func:`whole_shapes`): the working
legs in pairs along the trunk with an odd one behind it, and every unit in one chain.

Two candidates that are the same body (the same key, or mirror images where the task is
symmetric) are one candidate.
"""

from __future__ import annotations

import itertools
from collections.abc import Iterator, Sequence
from dataclasses import dataclass

import numpy as np

from qdsega.reform.arrangement import (
    Arrangement,
    Material,
    Move,
    Place,
    side_connectors,
    straight_connector,
)
from qdsega.reform.plan import plan

AS_IT_IS = "the body as it is"
MOVED = "moved"
CHAIN = "one chain"
PAIRS = "legs in pairs, one behind"
SPREAD = "legs in pairs spread along the trunk, one behind"


@dataclass(frozen=True)
class Candidate:
    """A body the units can take.

    Attributes:
        name: ``c00`` for the body as it is, then ``c01``, ``c02``, ... in the order found.
        arrangement: where each unit hangs.
        moves: the fewest moves from the body as it is (:mod:`qdsega.reform.plan`).
        how: the body as it is, a whole shape's name, or "moved".
    """

    name: str
    arrangement: Arrangement
    moves: tuple[Move, ...]
    how: str


class Candidates:
    """The candidates found so far, each body once; new ones are named in order."""

    def __init__(self, material: Material, *, symmetric: bool) -> None:
        self.material = material
        self.symmetric = symmetric
        self.found: list[Candidate] = []
        self._keys: set[str] = set()
        self.add(material.start(), AS_IT_IS)

    def add(self, arrangement: Arrangement, how: str) -> bool:
        """Keep ``arrangement`` unless it is a body found already or (but for the body as it
        is) has no working joint; with the fewest moves from the body as it is, its units
        named as the moves leave them (:func:`qdsega.reform.plan.plan`)."""
        key = shape_key(arrangement, symmetric=self.symmetric)
        working = bool(arrangement.formation("", "").joints) or how == AS_IT_IS
        if key in self._keys or not working:
            return False
        self._keys.add(key)
        moves, renamed = plan(self.material.start(), arrangement)
        self.found.append(Candidate(f"c{len(self.found):02d}", renamed, tuple(moves), how))
        return True

    def by_name(self, name: str) -> Candidate:
        return next(c for c in self.found if c.name == name)

    def first_round(self) -> list[Candidate]:
        """Every body one move away, and the whole shapes."""
        before = len(self.found)
        start = self.found[0]
        for move in moves_from(start.arrangement):
            self.add(start.arrangement.moved(move), MOVED)
        for how, arrangement in whole_shapes(self.material):
            self.add(arrangement, how)
        return self.found[before:]

    def next_round(self, best: Sequence[Candidate]) -> list[Candidate]:
        """Every body one more attaching move away from each of ``best`` (setting a part
        aside is tried in the first round, on the body as it is)."""
        before = len(self.found)
        for candidate in best:
            for move in moves_from(candidate.arrangement, set_aside=False):
                self.add(candidate.arrangement.moved(move), MOVED)
        return self.found[before:]


def shape_key(arrangement: Arrangement, *, symmetric: bool) -> str:
    """The body's key; where the task is mirror-symmetric, the lesser of it and its mirror
    image's, so that a body and its mirror image are one candidate."""
    key = arrangement.key()
    if not symmetric:
        return key
    mirror = arrangement.key(mirror=True)
    return min(key, mirror) if mirror else key


def parts(arrangement: Arrangement) -> list[str]:
    """What a move takes: every leg (by its top unit) and every trunk unit but the root, with
    what hangs from it."""
    material = arrangement.material
    return [
        name
        for name in material.units
        if name != material.root and (name in material.leg_tops or material.is_trunk(name))
    ]


def moves_from(arrangement: Arrangement, *, set_aside: bool = True) -> Iterator[Move]:
    """The moves tried from ``arrangement``: a part to a free connector of a trunk unit, or
    (``set_aside``) set aside; a part set aside back onto such a connector."""
    material = arrangement.material
    targets = [p for p in arrangement.free() if material.is_trunk(p.parent)]
    for part in parts(arrangement):
        place = arrangement.place(part)
        for target in targets:
            move = Move(part, place, target)
            if arrangement.can(move):
                yield move
        if place is not None and set_aside:
            yield Move(part, place, None)


def whole_shapes(material: Material) -> list[tuple[str, Arrangement]]:
    """The chain, and the working legs in pairs with an odd one behind (pairs from the front,
    and pairs spread evenly), where the units allow them."""
    start = material.start()
    shapes = []
    chain = _chain(start)
    if chain is not None:
        shapes.append((CHAIN, chain))
    for how, spread in ((PAIRS, False), (SPREAD, True)):
        paired = _pairs(start, spread=spread)
        if paired is not None:
            shapes.append((how, paired))
    return shapes


def _chain(start: Arrangement) -> Arrangement | None:
    """Every unit in one line, each hanging from the straight connector of the one before:
    the trunk first, then each leg's units, then the other spares."""
    material = start.material
    trunk = [n for n in material.units if material.is_trunk(n)]
    trunk.sort(
        key=lambda n: start.attached.index(n) if n in start.attached else len(material.units)
    )
    tops = {leg.name: top for top, leg in material.leg_tops.items()}
    legs = [n for leg in material.legs for n in start.subtree(tops[leg.name]) if n in leg.units]
    rest = [n for n in material.units if n not in trunk and n not in legs]
    order = trunk + legs + rest
    places: dict[str, Place | None] = {}
    for previous, name in itertools.pairwise(order):
        connector = straight_connector(material.units[previous].unit_type)
        if connector is None:
            return None
        places[name] = Place(previous, connector)
    return Arrangement(material, tuple((n, places.get(n)) for n, _ in start.places))


def _pairs(start: Arrangement, *, spread: bool) -> Arrangement | None:
    """The working legs in left-right pairs on the trunk units that have both sides, from the
    front or spread evenly along the trunk, an odd one on the straight connector of the last
    trunk unit; broken legs set aside. A leg already in a slot of the shape stays there."""
    material = start.material
    frames = start.frames()
    trunk = [n for n in start.attached if material.is_trunk(n)]
    slots: list[tuple[Place, Place]] = []
    for unit in trunk:
        sides = side_connectors(material.units[unit].unit_type, frames[unit])
        held = start.children(unit)
        if len(sides) == 2 and not any(
            material.is_trunk(held[c]) for c in sides.values() if c in held
        ):
            slots.append((Place(unit, sides["left"]), Place(unit, sides["right"])))
    working = [
        leg for leg in material.legs if all(material.units[n].locked_rad is None for n in leg.units)
    ]
    pairs = len(working) // 2
    if not working or pairs > len(slots):
        return None
    at = np.linspace(0, len(slots) - 1, pairs).round().astype(int) if spread else range(pairs)
    targets = [place for k in at for place in slots[k]]
    if len(working) % 2:
        last = trunk[-1]
        connector = straight_connector(material.units[last].unit_type)
        if connector is None or any(material.is_trunk(c) for c in start.children(last).values()):
            return None
        targets.append(Place(last, connector))
    tops = [next(n for n in leg.units if n in material.leg_tops) for leg in working]
    free = list(targets)
    placed: dict[str, Place | None] = {}
    for top in tops:  # a leg already in a slot of the shape keeps it
        place = start.place(top)
        if place is not None and place in free:
            placed[top] = place
            free.remove(place)
    for top in tops:
        if top not in placed:
            placed[top] = free.pop(0)
    leg_tops = set(material.leg_tops)
    places = tuple((n, placed.get(n, None if n in leg_tops else p)) for n, p in start.places)
    return Arrangement(material, places)
