import math

import numpy as np
import pytest

from qdsega.assembly import assemble
from qdsega.description import load_formation
from qdsega.simulation.bullet import BulletSimulation
from qdsega.simulation.camera import (
    FRAMING,
    MIN_DISTANCE_M,
    UNIT_SIZE_M,
    CameraConfig,
    body_extent_m,
)


@pytest.mark.parametrize("egl", [True, False], ids=["egl", "tiny-renderer"])
def test_camera_sees_the_robot_and_the_light(egl):
    formation = load_formation("assemblies/snake5.yaml")
    with BulletSimulation(robot=assemble(formation), egl=egl) as sim:
        assert sim.egl_enabled == egl, "pybullet's EGL plugin loads here (Mesa llvmpipe)"
        sim.reset(np.zeros(4))
        sim.add_light((3.0, 0.0), radius_m=0.3)
        image = sim.camera_image(
            width=160,
            height=120,
            target_m=(-0.2, 0.0, 0.0),
            view_yaw_rad=0.0,
            distance_m=0.8,
            pitch_rad=math.radians(20),
            fov_deg=60.0,
        )
    assert image.shape == (120, 160, 3) and image.dtype == np.uint8
    blue = (image[..., 2] > 150) & (image[..., 0] < 90)  # servo housing (0.16, 0.36, 0.78)
    yellow = (image[..., 0] > 200) & (image[..., 1] > 150) & (image[..., 2] < 90)  # the light
    assert blue[40:, 40:120].mean() > 0.01, "the snake shows in the lower middle"
    assert yellow.any(), "the light shows ahead"


def test_the_default_camera_frames_the_body_at_640x480():
    camera = CameraConfig()
    assert (camera.width, camera.height, camera.distance_m) == (640, 480, None)
    assert camera.distance_for(0.5) == pytest.approx(FRAMING * 0.5)
    assert camera.distance_for(0.01) == MIN_DISTANCE_M  # one unit: not inside it
    assert CameraConfig(distance_m=2.0).distance_for(0.5) == 2.0  # given: kept
    with pytest.raises(ValueError, match="distance_m must be positive"):
        CameraConfig(distance_m=0.0)


def test_the_extent_is_the_widest_horizontal_span_of_the_units_plus_one_unit():
    centres = np.array([[0.0, 0.0, 0.05], [0.3, 0.0, 0.2], [0.0, 0.4, 0.05]])
    assert body_extent_m(centres) == pytest.approx(0.5 + UNIT_SIZE_M)  # heights do not count
    assert body_extent_m(centres[:1]) == pytest.approx(UNIT_SIZE_M)
