"""The plan: the fewest moves from a body to another, by hand and against a search of every
move sequence; units that are alike trade roles."""

from __future__ import annotations

from collections.abc import Iterator

from qdsega.description import load_formation, resolve_formation
from qdsega.reform.arrangement import Arrangement, Material, Move, Place
from qdsega.reform.candidates import Candidates, whole_shapes
from qdsega.reform.material import material_of
from qdsega.reform.plan import plan


def material(name: str) -> Material:
    return material_of(load_formation(resolve_formation(name)), {})


def test_a_body_to_itself_is_no_move():
    start = material("quadruped").start()
    assert plan(start, start) == ([], start)


def test_one_leg_behind_the_trunk_is_one_move():
    start = material("quadruped_tripod").start()
    target = start.moved(Move("L2_swing", Place("body2", "left"), Place("body2", "back")))
    moves, renamed = plan(start, target)
    assert [str(m) for m in moves] == ["L2_swing: body2.left -> body2.back"]
    assert renamed == target


def test_alike_legs_trade_roles_so_that_a_swap_is_no_move():
    start = material("quadruped").start()
    places = dict(start.places)  # L1 and L2 swap their connectors: the same body
    places["L1_swing"], places["L2_swing"] = places["L2_swing"], places["L1_swing"]
    swapped = Arrangement(start.material, tuple(places.items()))
    assert swapped != start and swapped.key() == start.key()
    moves, renamed = plan(start, swapped)
    assert moves == [] and renamed == start


def test_the_quadruped_as_a_chain_is_four_moves():
    start = material("quadruped").start()
    chain = dict(whole_shapes(start.material))["one chain"]
    moves, renamed = plan(start, chain)
    assert [str(m) for m in moves] == [
        "L1_swing: body1.left -> body2.back",
        "L2_swing: body2.left -> L1_lift.back",
        "R1_swing: body1.right -> L2_lift.back",
        "R2_swing: body2.right -> R1_lift.back",
    ]
    assert renamed.key() == chain.key()


def test_a_move_that_waits_on_another_comes_after_it():
    """The trunk unit behind is set aside once the leg that goes behind it has gone there."""
    start = material("quadruped_tripod").start()
    target = start.moved(Move("L1_swing", Place("body1", "left"), Place("body2", "back")))
    target = target.moved(Move("body2", Place("body1", "back"), None))
    moves, _ = plan(start, target)
    assert [str(m) for m in moves] == [
        "L1_swing: body1.left -> body2.back",
        "body2: body1.back -> the spares",
    ]


def every_move(arrangement: Arrangement) -> Iterator[Arrangement]:
    """Every body one move away: any unit (with what hangs from it) to any free connector
    of the body, or set aside."""
    for name, place in arrangement.places:
        targets = [*arrangement.free(), None] if place is not None else list(arrangement.free())
        for target in targets:
            move = Move(name, place, target)
            if arrangement.can(move):
                yield arrangement.moved(move)


def fewest_by_search(start: Arrangement, limit: int) -> dict[str, int]:
    """The fewest moves to every body up to ``limit`` moves away, by trying every sequence."""
    fewest = {start.key(): 0}
    frontier = [start]
    for depth in range(1, limit + 1):
        frontier = [b for a in frontier for b in every_move(a) if b.key() not in fewest]
        for body in frontier:
            fewest.setdefault(body.key(), depth)
    return fewest


def test_the_plan_is_the_fewest_moves():
    found = Candidates(material("quadruped_tripod"), symmetric=False)
    found.next_round(found.first_round()[:2])
    fewest = fewest_by_search(found.material.start(), 2)
    for candidate in found.found:
        key = candidate.arrangement.key()
        if key in fewest:
            assert len(candidate.moves) == fewest[key]
        else:  # the chain: farther than a search of every sequence reaches here
            assert len(candidate.moves) > 2
