import math

import numpy as np
import pytest

from qdsega.assembly import assemble
from qdsega.description import load_formation
from qdsega.simulation.bullet import BulletSimulation


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
