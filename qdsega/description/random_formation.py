"""Random valid formations, as YAML data, for fuzzing the reader, assembler and simulator.

Built from the shipped ``servo`` and ``hub`` units so that no two units overlap in the rest
posture: a *trunk* (a chain along ``back`` connectors, each unit a servo or a hub), *limbs*
(chains of one to three servos on a trunk unit's ``left`` or ``right`` connector) and *leg
pairs* (a two-servo leg template, left and right of a trunk hub). Every joint but a leg's has
a level at 0 deg, which the rest posture picks, so trunk and limbs rest straight; legs rest
forward and down. Axes are named or arbitrary vectors; levels are lists or ranges; one servo
joint in ten is broken, locked at 0 deg.
"""

from __future__ import annotations

from typing import Any

import numpy as np

_AXES = ("yaw", "pitch", "roll")


def random_formation(rng: np.random.Generator, *, name: str = "random") -> dict[str, Any]:
    """A random formation that ``load_formation`` accepts, as plain YAML data.

    Args:
        rng: the only source of randomness; the same state gives the same formation.
        name: the formation's name.
    """
    trunk_types = _trunk_types(rng)
    units: list[dict[str, Any]] = [{"name": "t1", "unit": trunk_types[0]}]
    if len(trunk_types) > 1 and len(set(trunk_types)) == 1 and rng.random() < 0.5:
        units.append(
            {"name": "t{i}", "repeat": [2, len(trunk_types)], "unit": trunk_types[0]}
            | {"parent": "t{i-1}", "connector": "back"}
            | _joint(rng, trunk_types[0])
        )
    else:
        for k, kind in enumerate(trunk_types[1:], start=2):
            units.append(
                {"name": f"t{k}", "unit": kind, "parent": f"t{k - 1}", "connector": "back"}
                | _joint(rng, kind)
            )
    has_legs = False
    for k, kind in enumerate(trunk_types, start=1):
        if kind == "hub" and rng.random() < 0.6:
            has_legs = True
            for side in ("left", "right"):
                leg = {"name": f"{side[0].upper()}{k}", "template": "leg", "parent": f"t{k}"}
                units.append(leg | {"connector": side, "side": side})
            continue
        for side in ("left", "right"):
            if rng.random() < 0.3:
                units.extend(_limb(rng, f"t{k}", side))
    if rng.random() < 0.3:
        rng.shuffle(units)  # declaration order is free: a unit may come before its parent
    formation: dict[str, Any] = {
        "name": name,
        "light": {
            "distance_m": float(round(rng.uniform(1.0, 100.0), 2)),
            "bearing_deg": int(rng.integers(-180, 181)),
        },
        "friction": _friction(rng),
        "units": units,
    }
    if has_legs:
        formation["templates"] = {"leg": _leg_template(rng)}
        mirrored = formation["templates"]["leg"]["units"][0]["levels_deg"][::-1]
        for unit in units:
            if unit.get("side") == "right":
                unit["overrides"] = {"swing": {"levels_deg": mirrored}}
    return formation


def _trunk_types(rng: np.random.Generator) -> list[str]:
    count = int(rng.integers(1, 9))
    if rng.random() < 0.4:
        return [str(rng.choice(["servo", "hub"]))] * count
    return [str(kind) for kind in rng.choice(["servo", "hub"], size=count)]


def _joint(rng: np.random.Generator, kind: str) -> dict[str, Any]:
    """A servo's ``axis`` and ``levels_deg`` (levels always include 0), sometimes
    ``locked_deg: 0`` too; nothing for a hub."""
    if kind != "servo":
        return {}
    if rng.random() < 0.8:
        axis: Any = str(rng.choice(_AXES))
    else:
        axis = [float(round(x, 3)) for x in rng.uniform(-1.0, 1.0, size=3)]
        axis[int(rng.integers(3))] = 1.0  # never the zero vector
    if rng.random() < 0.5:
        step = int(rng.choice([5, 10, 15, 20]))
        low, high = -step * int(rng.integers(0, 5)), step * int(rng.integers(0, 5))
        levels: Any = {"min": low, "max": high, "step": step}
    else:
        others = rng.choice(np.arange(-60, 61, 5), size=int(rng.integers(0, 6)), replace=False)
        levels = [0, *(int(x) for x in others if x != 0)]
        rng.shuffle(levels)
    locked = {"locked_deg": 0} if rng.random() < 0.1 else {}
    return {"axis": axis, "levels_deg": levels} | locked


def _limb(rng: np.random.Generator, parent: str, side: str) -> list[dict[str, Any]]:
    """A chain of servos on ``parent``'s ``side`` connector."""
    names = [f"{parent}_{side}{k}" for k in range(1, int(rng.integers(1, 4)) + 1)]
    limb = []
    for k, name in enumerate(names):
        attach = (parent, side) if k == 0 else (names[k - 1], "back")
        unit: dict[str, Any] = {
            "name": name,
            "unit": "servo",
            "parent": attach[0],
            "connector": attach[1],
        }
        if rng.random() < 0.2:
            unit["friction"] = {"lateral": float(round(rng.uniform(0.2, 2.0), 2))}
        limb.append(unit | _joint(rng, "servo"))
    return limb


def _leg_template(rng: np.random.Generator) -> dict[str, Any]:
    swing = int(rng.choice([10, 15, 20]))
    down, up = int(rng.choice([-45, -35, -25])), int(rng.choice([0, 5, 10]))
    return {
        "leg": {"swing": "swing", "lift": "lift"},
        "units": [
            {"name": "swing", "unit": "servo", "axis": "yaw", "levels_deg": [-swing, swing]},
            {"name": "lift", "unit": "servo", "parent": "swing", "connector": "back"}
            | {"axis": "pitch", "levels_deg": [down, up]},
        ],
    }


def _friction(rng: np.random.Generator) -> dict[str, Any]:
    lateral = float(round(rng.uniform(0.3, 1.2), 2))
    if rng.random() < 0.5:
        return {"lateral": lateral}
    along, vertical = (float(round(x, 2)) for x in rng.uniform(0.01, 1.0, size=2))
    return {"lateral": lateral, "anisotropic": [along, 1.0, vertical]}
