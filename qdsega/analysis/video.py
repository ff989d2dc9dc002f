"""Write frames as an MP4 (H.264, through imageio-ffmpeg's bundled ffmpeg) or an animated GIF."""

from __future__ import annotations

from pathlib import Path

import imageio.v3 as iio
import numpy as np

from qdsega.atomic import replaced_atomically

VIDEO_SUFFIXES = (".mp4", ".gif")


def write_video(frames: list[np.ndarray], out: Path, *, fps: int) -> None:
    """Write ``frames`` (each (H, W, 3) uint8) to ``out``; the suffix picks the format.

    The file is written next to ``out`` first and then renamed, so a failed write leaves
    nothing behind.
    """
    out = Path(out)
    if out.suffix.lower() not in VIDEO_SUFFIXES:
        raise ValueError(f"video must end in {' or '.join(VIDEO_SUFFIXES)}, got {out.name}")
    if not frames:
        raise ValueError("no frames to write")
    out.parent.mkdir(parents=True, exist_ok=True)
    with replaced_atomically(out) as partial:
        if out.suffix.lower() == ".gif":
            iio.imwrite(partial, np.stack(frames), duration=1000.0 / fps, loop=0)
        else:
            iio.imwrite(
                partial,
                np.stack(frames),
                fps=fps,
                codec="libx264",
                macro_block_size=1,
                plugin="FFMPEG",
            )
