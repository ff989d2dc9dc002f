"""Film a formation executing a posture sequence, off-screen, through its Gymnasium env.

The env (:class:`qdsega.locomotion.env.LocomotionEnv` with ``render_mode="rgb_array"``) starts
the trial as it starts every trial (start posture, settle, snapshot), so the film shows the
motion the env simulates, step for step the one ``qdsega evaluate`` measures.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:  # the env starts PyBullet
    from qdsega.locomotion.env import LocomotionEnv


@dataclass(frozen=True)
class Film:
    """Frames of a recording.

    Attributes:
        frames: RGB images, each (height, width, 3), uint8.
        fps: frames per second of simulated time.
        failure: why the lower agent stopped early, if it did.
    """

    frames: list[np.ndarray]
    fps: int
    failure: str | None


def record(env: LocomotionEnv, postures: np.ndarray) -> Film:
    """Reset ``env`` and execute ``postures`` (steps, J) of level indices, filming the start and
    then every 1/fps s of simulated time (``env.camera.fps``), until the postures end or the
    lower agent fails.

    Raises:
        ValueError: ``env`` does not render (``render_mode`` is not ``"rgb_array"``).
    """
    if env.render_mode != "rgb_array":
        raise ValueError(f"record needs render_mode='rgb_array', got {env.render_mode!r}")
    fps = env.camera.fps
    every = max(1, round(1.0 / (fps * env.sim.settings.time_step_s)))
    env.reset(seed=0)
    frames = [picture(env)]
    physics_steps = 0

    def film() -> None:
        nonlocal physics_steps
        physics_steps += 1
        if physics_steps % every == 0:
            frames.append(picture(env))

    failure = None
    env.on_physics_step = film
    try:
        for posture in postures:
            _, _, terminated, _, info = env.step(np.asarray(posture))
            if terminated:
                failure = info["failure"]
                break
    finally:
        env.on_physics_step = None
    return Film(frames=frames, fps=fps, failure=failure)


def picture(env: LocomotionEnv) -> np.ndarray:
    """The camera's picture now, (height, width, 3) uint8, of an env made to render
    (``render_mode`` ``"rgb_array"``)."""
    image = env.render()
    assert image is not None  # only an env without a render mode pictures nothing
    return image
