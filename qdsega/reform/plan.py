"""The fewest moves from one body to another made of the same units.

A unit's place changes only when it is the unit moved, so a body needs at least one move for
each unit that must hang elsewhere; in an order where each target connector is free when its
unit comes, that many moves suffice. Units that are alike can trade roles: whole legs of the
same shape, and trunk units of the same kind (type, axis, lock and friction). The plan
takes the trade that leaves the most units where they are, and the target is renamed to
match, so that the plan and the re-formed body's file name the same units.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Iterator
from typing import Any

from qdsega.reform.arrangement import Arrangement, Move, Place

MAX_TRADES = 5040
"""Trunk units are traded in every way while the ways number at most this (7!); beyond it
they keep their names and only legs trade."""


def plan(start: Arrangement, target: Arrangement) -> tuple[list[Move], Arrangement]:
    """The moves from ``start`` to ``target`` (the same material) and ``target`` renamed to
    the units that the moves put there.

    Raises:
        ValueError: ``target`` is not made of ``start``'s material.
    """
    if start.material is not target.material:
        raise ValueError("the two bodies are not made of the same material")
    best: tuple[int, Arrangement] | None = None
    for traded in _trades(start, target):
        count = sum(traded.place(n) != start.place(n) for n, _ in start.places)
        if best is None or count < best[0]:
            best = (count, traded)
    assert best is not None
    renamed = best[1]
    return _ordered(start, renamed), renamed


def _trades(start: Arrangement, target: Arrangement) -> Iterator[Arrangement]:
    """``target`` renamed by each way of trading alike trunk units (all ways, or none when
    there are too many), legs then traded to keep as many in place as can be."""
    groups = _trunk_groups(start)
    ways = math.prod(math.factorial(len(g)) for g in groups)
    orders = (
        itertools.product(*(itertools.permutations(g) for g in groups))
        if ways <= MAX_TRADES
        else [tuple(tuple(g) for g in groups)]
    )
    for order in orders:
        names = {
            a: b
            for group, new in zip(groups, order, strict=True)
            for a, b in zip(group, new, strict=True)
        }
        yield _trade_legs(start, _renamed(target, names))


def _kind(arrangement: Arrangement, name: str) -> tuple[Any, ...]:
    unit = arrangement.material.units[name]
    return (unit.unit_type.name, unit.axis, unit.locked_rad, unit.friction)


def _trunk_groups(start: Arrangement) -> list[list[str]]:
    """Trunk units (the root left out) grouped by kind."""
    material = start.material
    groups: dict[tuple[Any, ...], list[str]] = {}
    for name in material.units:
        if name != material.root and material.is_trunk(name):
            groups.setdefault(_kind(start, name), []).append(name)
    return [g for g in groups.values() if len(g) > 1]


def _leg_shape(start: Arrangement, top: str) -> tuple[Any, ...]:
    """What makes two legs alike: their units' kinds and how they hang together."""
    leg = start.material.leg_tops[top]
    units = start.material.units
    inner = tuple(
        (_kind(start, n), leg.units.index(units[n].parent) if units[n].parent in leg.units else -1)
        for n in leg.units
    )
    return inner


def _trade_legs(start: Arrangement, target: Arrangement) -> Arrangement:
    """``target`` with alike legs traded so that each leg already where ``target`` has one of
    its shape stays there."""
    material = start.material
    names: dict[str, str] = {}
    by_shape: dict[tuple[Any, ...], list[str]] = {}
    for top in material.leg_tops:
        by_shape.setdefault(_leg_shape(start, top), []).append(top)
    for tops in by_shape.values():
        # the target's leg at each slot, and which of the start's legs is there now
        wanted = {top: target.place(top) for top in tops}
        stay = {top: top for top in tops if start.place(top) is not None}
        owner: dict[str, str] = {}
        for top in tops:  # target leg -> start leg already at its slot
            for other in stay:
                if other not in owner.values() and start.place(other) == wanted[top]:
                    owner[top] = other
                    break
        spare = [t for t in tops if t not in owner.values()]
        for top in tops:
            if top not in owner:
                owner[top] = spare.pop(0)
        for top, other in owner.items():
            old, new = material.leg_tops[top], material.leg_tops[other]
            names.update(zip(old.units, new.units, strict=True))
    return _renamed(target, names)


def _renamed(target: Arrangement, names: dict[str, str]) -> Arrangement:
    """``target`` with the units ``names`` maps playing each other's roles: unit ``b =
    names[a]`` hangs where ``a`` hung, from the renamed parent."""
    if not names:
        return target
    moved: dict[str, Place | None] = {}
    for name, place in target.places:
        where = (
            None if place is None else Place(names.get(place.parent, place.parent), place.connector)
        )
        moved[names.get(name, name)] = where
    return type(target)(target.material, tuple((n, moved[n]) for n, _ in target.places))


def _ordered(start: Arrangement, target: Arrangement) -> list[Move]:
    """Moves that take ``start`` to ``target``, one per unit that hangs elsewhere, each made
    when its connector is free; a unit in the way of all the others is set aside first (one
    move more)."""
    current = start
    pending = [n for n, _ in start.places if target.place(n) != start.place(n)]
    moves: list[Move] = []
    while pending:
        # attachments first: a part is set aside once what its target holds hangs from it
        for name in sorted(pending, key=lambda n: target.place(n) is None):
            move = Move(name, current.place(name), target.place(name))
            if current.can(move):
                break
        else:  # every pending move waits on another: set one aside
            name = next(n for n in pending if current.place(n) is not None)
            move = Move(name, current.place(name), None)
            current = current.moved(move)
            moves.append(move)
            continue
        current = current.moved(move)
        moves.append(move)
        pending.remove(name)
    if current.places != target.places:
        raise AssertionError("the moves did not reach the target")
    return moves
