"""Rough ground in pictures: its relief shows, in its texture and through either renderer."""

import math

import numpy as np
import pytest

from qdsega.assembly import assemble
from qdsega.description import load_formation, named_world
from qdsega.simulation.bullet import BulletSimulation
from qdsega.simulation.terrain import RELIEF_SUN_DEG, relief_texture, rough_heights

RUBBLE = named_world("rubble")


def test_the_texture_is_lighter_where_the_ground_is_higher_and_where_it_faces_the_sun():
    texture = relief_texture(RUBBLE.rough).astype(float).mean(axis=-1)
    n = len(texture)
    heights = rough_heights(RUBBLE.rough)
    cells = np.linspace(0, len(heights) - 1, n).round().astype(int)
    height = heights[np.ix_(cells, cells)]
    assert texture[height > np.quantile(height, 0.9)].mean() > (
        texture[height < np.quantile(height, 0.1)].mean() + 20
    )
    slope_x, slope_y = np.gradient(height)
    azimuth = math.radians(RELIEF_SUN_DEG[0])
    toward_sun = -(slope_x * math.cos(azimuth) + slope_y * math.sin(azimuth))  # rises away
    middle = np.abs(height - np.median(height)) < 0.1 * RUBBLE.rough.amplitude_m
    facing = middle & (toward_sun > np.quantile(toward_sun, 0.8))
    away = middle & (toward_sun < np.quantile(toward_sun, 0.2))
    assert texture[facing].mean() > texture[away].mean() + 20


@pytest.mark.parametrize("egl", [True, False], ids=["egl", "tiny-renderer"])
def test_a_picture_of_rough_ground_shows_its_relief(egl, monkeypatch):
    if not egl:
        monkeypatch.setattr(BulletSimulation, "_load_egl", lambda self: False)
    formation = load_formation("assemblies/snake5.yaml")
    with BulletSimulation(robot=assemble(formation), egl=True, world=RUBBLE) as sim:
        assert sim.egl_enabled == egl
        sim.reset(np.zeros(4))
        image = sim.camera_image(
            width=80,
            height=60,
            target_m=(3.0, -2.0, 0.0),  # ahead and to the right: ground alone, no edge, no body
            view_yaw_rad=0.0,
            distance_m=1.5,
            pitch_rad=math.radians(80),
            fov_deg=60.0,
        )
    brightness = image.astype(float).mean(axis=-1)
    assert brightness.std() > 10, "an evenly lit plane, as rough ground looked before"
