"""Pictures of what the project ships: every body standing at its start on flat ground, every
world with a body in it for scale, a contact sheet of each, a diagram of each unit type and a
leg in each of its four states. ``qdsega gallery`` draws them; ``docs/gallery.md`` shows them.
"""

from __future__ import annotations

import math
import xml.etree.ElementTree as ET
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
from matplotlib.figure import Figure
from mpl_toolkits.mplot3d.art3d import Poly3DCollection

from qdsega.analysis.pictures import figure_pixels, save_png
from qdsega.analysis.render import rest_still
from qdsega.assembly.mass_properties import shape_mesh
from qdsega.description import Formation, UnitType, World, load_formation, resolve_formation
from qdsega.description.unit_type import LINK_PLACEHOLDER
from qdsega.errors import WorldError
from qdsega.locomotion.env import LocomotionEnv
from qdsega.msm.legs import LEG_STATE_NAMES, LEG_STATES, LegLayout
from qdsega.simulation.camera import CameraConfig

BODY_TURN_DEG = -40.0
"""A body's still: the camera turned this far around it from behind (deg), a three-quarter
view that shows a snake's length and a walker's legs on both sides."""
BODY_PITCH_DEG = 30.0
"""A body's still: how far the camera looks down (deg)."""
WORLD_DISTANCE_M = 2.5
"""A world's still: the camera's distance from the body (m), far enough to show the ground
ahead of it."""
WORLD_VIEW_DEG = (-25.0, 35.0)
"""A world's still: the camera turned around the body from behind and looking down (deg):
steps, walls and a roof ahead are seen a little from the side."""
CORRIDOR_VIEW_DEG = (-25.0, 60.0)
"""The same, between walls: from high enough to see the body between them."""
SLOPE_VIEW_DEG = (90.0, 10.0)
"""The same, on a slope: from the side, low, so that the ground rises against the horizon."""
WORLD_BODIES = ("quadruped", "snake5")
"""The body shown in a world for scale: the first of these that can start there (a legged body
cannot start between the corridor's walls)."""
LEG_BODY = "quadruped"
"""The body whose front left leg shows the leg states."""
LEG_VIEW_DEG = (-60.0, 35.0)
"""The leg states: the camera's heading (counter-clockwise from the body's, deg) and how far
it looks down (deg): from behind and to the left of the leg, so that it shows both moving
forward and back and going up and down."""
LEG_DISTANCE_M = 0.55
"""The leg states: the camera's distance from the leg (m)."""
LEG_RGBA = (0.85, 0.2, 0.15, 1.0)
"""The leg states: the leg's colour, to tell it from the others."""
UNIT_AXIS_COLOURS = ("tab:red", "tab:green", "tab:blue")
"""A unit diagram's x, y and z axes."""
UNIT_CONNECTOR_COLOUR = "purple"
"""A unit diagram's connectors."""
UNIT_EDGE_RAD = 0.5
"""A unit diagram draws the edges between faces meeting at more than this angle (rad): a box's
edges and a cylinder's rims, not the facets of its side."""
SHEET_COLUMNS = 3
"""Pictures a row of a contact sheet."""
SHEET_TILE_IN = 3.2
"""A contact sheet's picture's width (inch, at 100 dpi)."""
PNG_COLOURS = 128
"""Colours of a written picture's palette: renders of a few flat colours need no more, and a
palette makes the file a fraction of its size. They are chosen to cover the picture's colours
(not its pixels), so that a small body keeps its colours on a large ground."""


@dataclass(frozen=True)
class Drawn:
    """What a gallery wrote: each group's pictures in order, its contact sheet last."""

    bodies: list[Path]
    worlds: list[Path]
    units: list[Path]
    legs: list[Path]


def draw_gallery(
    out: Path,
    *,
    formations: Sequence[Formation],
    worlds: Sequence[World],
    units: Sequence[UnitType],
    camera: CameraConfig,
) -> Drawn:
    """Draw every formation (``OUT/bodies/NAME.png``), every world with a body in it
    (``OUT/worlds/NAME.png``), a contact sheet of each group (``OUT/bodies.png``,
    ``OUT/worlds.png``), a diagram of each unit type (``OUT/unit_NAME.png``) and a leg in
    each leg state (``OUT/leg_states.png``). ``camera`` gives the stills' size."""
    bodies = [(f.name, f.name, body_still(f, camera)) for f in formations]
    in_worlds = []
    for world in worlds:
        body, still = _with_a_body(world, camera)
        in_worlds.append((world.name, f"{world.name} ({body.name})", still))
    return Drawn(
        bodies=_group(bodies, out / "bodies", "bodies at their start"),
        worlds=_group(in_worlds, out / "worlds", "worlds, with a body for scale"),
        units=[_save_figure(unit_diagram(u), out / f"unit_{u.name}.png") for u in units],
        legs=[_save_png(leg_states(camera), out / "leg_states.png")],
    )


def body_still(formation: Formation, camera: CameraConfig) -> np.ndarray:
    """``formation`` standing at its start posture on flat ground, (height, width, 3) uint8,
    seen from behind and to the side."""
    view = CameraConfig(width=camera.width, height=camera.height, pitch_deg=BODY_PITCH_DEG)
    return rest_still(formation, view, turn_deg=BODY_TURN_DEG)


def world_still(world: World, body: Formation, camera: CameraConfig) -> np.ndarray:
    """``body`` at its start in ``world``, (height, width, 3) uint8, the ground ahead in view.

    Raises:
        WorldError: ``body`` cannot start there (it starts inside an obstacle).
    """
    turn, pitch = WORLD_VIEW_DEG
    if world.corridor is not None:
        turn, pitch = CORRIDOR_VIEW_DEG
    elif world.slope_rad != 0.0:
        turn, pitch = SLOPE_VIEW_DEG
    view = CameraConfig(
        width=camera.width, height=camera.height, distance_m=WORLD_DISTANCE_M, pitch_deg=pitch
    )
    return rest_still(body, view, world=world, turn_deg=turn)


def _with_a_body(world: World, camera: CameraConfig) -> tuple[Formation, np.ndarray]:
    """The first of ``WORLD_BODIES`` that can start in ``world``, and its still there."""
    for name in WORLD_BODIES:
        body = load_formation(resolve_formation(name))
        try:
            return body, world_still(world, body, camera)
        except WorldError:
            continue
    raise WorldError(f"none of {', '.join(WORLD_BODIES)} can start in {world.name}")


def leg_states(camera: CameraConfig) -> np.ndarray:
    """A contact sheet, (height, width, 3) uint8, of ``LEG_BODY``'s front left leg (in red) in
    each leg state, the other legs at the start: the swing joint moves the leg forward or
    back, the lift joint puts it down or up."""
    body = load_formation(resolve_formation(LEG_BODY))
    layout = LegLayout.from_formation(body)
    leg = body.legs[0]
    view = CameraConfig(width=camera.width, height=camera.height)
    env = LocomotionEnv(formation=body, render_mode="rgb_array", camera=view)
    try:
        env.reset()
        env.sim.tint(leg.units, LEG_RGBA)
        rows = [k for k, unit in enumerate(body.units) if unit.name in leg.units]
        centres, _ = env.sim.unit_states(rows)
        start = np.array(env.start_levels)
        pictures = {}
        for state in LEG_STATES:
            states = layout.states(start)
            states[0] = state
            posture = layout.posture(states, base=start)
            env.sim.place_joints(env.sim.joint_ids, body.posture_rad(posture))
            pictures[f"{state}: {LEG_STATE_NAMES[state]}"] = env.sim.camera_image(
                width=camera.width,
                height=camera.height,
                target_m=(*centres.mean(axis=0)[:2], 0.03),
                view_yaw_rad=math.radians(LEG_VIEW_DEG[0]),  # the body heads along +x
                distance_m=LEG_DISTANCE_M,
                pitch_rad=math.radians(LEG_VIEW_DEG[1]),
                fov_deg=view.fov_deg,
            )
    finally:
        env.close()
    title = f"{body.name}'s leg {leg.name} (red) in each leg state; the body heads to the left"
    return figure_pixels(contact_sheet(pictures, title, columns=2))


def unit_diagram(unit: UnitType) -> Figure:
    """``unit`` drawn from its link template's visuals, with its frame's axes (the joint turns
    about one of them), its joint at the origin and its connectors, each with the direction
    a child attached there trails in."""
    link = ET.fromstring(unit.link_template.replace(LINK_PLACEHOLDER, unit.name)).find("link")
    visuals = [] if link is None else link.findall("visual")
    figure = plt.figure(figsize=(8.0, 6.0), dpi=100)
    axes = figure.add_subplot(projection="3d")
    bounds = [np.zeros((2, 3))]
    for visual in visuals:
        mesh = shape_mesh(visual, unit.folder)
        colour = visual.find("material/color")
        rgb = (
            (0.6, 0.6, 0.6)
            if colour is None
            else tuple(map(float, colour.get("rgba", "").split()[:3]))
        )
        faces = Poly3DCollection(mesh.vertices[mesh.faces], facecolor=(*rgb, 0.3), edgecolor="none")
        axes.add_collection3d(faces)
        sharp = mesh.face_adjacency_edges[mesh.face_adjacency_angles > UNIT_EDGE_RAD]
        for edge in mesh.vertices[sharp]:
            axes.plot(*edge.T, color=rgb, linewidth=1.0)
        bounds.append(mesh.bounds)
    low, high = np.min([b[0] for b in bounds], axis=0), np.max([b[1] for b in bounds], axis=0)
    size = float(np.max(high - low))
    arrow = 0.45 * size
    names = ("x (roll)", "y (pitch)", "z (yaw)") if unit.joint is not None else ("x", "y", "z")
    for k, (name, axis_colour) in enumerate(zip(names, UNIT_AXIS_COLOURS, strict=True)):
        tip = np.zeros(3)
        tip[k] = arrow
        axes.quiver(0, 0, 0, *tip, color=axis_colour, linewidth=2, arrow_length_ratio=0.15)
        axes.text(*(1.15 * tip), name, color=axis_colour, fontsize=10)
    axes.scatter([0], [0], [0], color="black", s=40, depthshade=False)
    for connector in unit.connectors.values():
        where = np.array(connector.xyz_m)
        trail = -_x_axis(connector.rpy_rad) * 0.45 * size
        axes.scatter(*where, color=UNIT_CONNECTOR_COLOUR, s=30, depthshade=False)
        axes.quiver(*where, *trail, color=UNIT_CONNECTOR_COLOUR, arrow_length_ratio=0.25)
        axes.text(
            *(where + 1.25 * trail), connector.name, color=UNIT_CONNECTOR_COLOUR, weight="bold"
        )
    margin = 0.15 * size
    span = np.array([np.minimum(low, -arrow) - margin, np.maximum(high, arrow) + margin])
    axes.set(
        xlim=span[:, 0],
        ylim=span[:, 1],
        zlim=span[:, 2],
        xlabel="x (m)",
        ylabel="y (m)",
        zlabel="z (m)",
    )
    axes.set_box_aspect(tuple(span[1] - span[0]), zoom=1.2)
    axes.tick_params(labelsize=7)
    for axis in (axes.xaxis, axes.yaxis, axes.zaxis):
        axis.set_pane_color((1.0, 1.0, 1.0, 0.0))
    figure.subplots_adjust(left=0.0, right=1.0, bottom=0.16, top=0.95)
    axes.view_init(elev=30, azim=-75)
    if unit.joint is None:
        joint = "the origin (black) attaches to the parent rigidly: a passive unit, no joint"
    else:
        limits = (math.degrees(unit.joint.lower_rad), math.degrees(unit.joint.upper_rad))
        joint = (
            "the joint is at the origin (black), where the unit attaches to its parent; it turns "
            f"{limits[0]:.0f}..{limits[1]:.0f} deg\nabout x, y or z (roll, pitch or yaw), as "
            "each unit of a formation says"
        )
    axes.set_title(f"unit {unit.name}: {unit.description}", fontsize=11)
    figure.text(
        0.5,
        0.02,
        f"{joint}\nconnectors ({UNIT_CONNECTOR_COLOUR}): where a child attaches; the arrow: the "
        "way the child's body trails (its -x)",
        ha="center",
        fontsize=9,
    )
    return figure


def _x_axis(rpy_rad: tuple[float, float, float]) -> np.ndarray:
    """The x axis of a frame turned by roll, pitch and yaw (rad, URDF's order), in its
    parent's frame."""
    _, pitch, yaw = rpy_rad
    return np.array(
        [math.cos(yaw) * math.cos(pitch), math.sin(yaw) * math.cos(pitch), -math.sin(pitch)]
    )


def contact_sheet(
    pictures: dict[str, np.ndarray], title: str, *, columns: int = SHEET_COLUMNS
) -> Figure:
    """The pictures in a grid of ``columns``, each under its name, with ``title`` above."""
    rows = math.ceil(len(pictures) / columns)
    first = next(iter(pictures.values()))
    aspect = first.shape[0] / first.shape[1]
    figure, grid = plt.subplots(
        rows,
        columns,
        figsize=(columns * SHEET_TILE_IN, rows * (SHEET_TILE_IN * aspect + 0.3) + 0.4),
        dpi=100,
        squeeze=False,
    )
    for axes, (name, picture) in zip(grid.flat, pictures.items(), strict=False):
        axes.imshow(picture)
        axes.set_title(name, fontsize=10)
    for axes in grid.flat:
        axes.axis("off")
    figure.suptitle(title, fontsize=12)
    figure.tight_layout()
    return figure


def _group(stills: list[tuple[str, str, np.ndarray]], folder: Path, title: str) -> list[Path]:
    """Each still (name, caption, picture) as ``folder/NAME.png``, then their contact sheet
    (each picture under its caption) as ``folder.png``."""
    files = [_save_png(still, folder / f"{name}.png") for name, _, still in stills]
    sheet = contact_sheet({caption: still for _, caption, still in stills}, title)
    return [*files, _save_figure(sheet, folder.with_suffix(".png"))]


def _save_figure(figure: Figure, file: Path) -> Path:
    return _save_png(figure_pixels(figure), file)


def _save_png(picture: np.ndarray, file: Path) -> Path:
    return save_png(picture, file, colours=PNG_COLOURS)
