"""Write frames as an MP4 (H.264, through imageio-ffmpeg's bundled ffmpeg) or an animated GIF
(Pillow)."""

from __future__ import annotations

from pathlib import Path

import imageio.v3 as iio
import numpy as np
from PIL import Image

from qdsega.atomic import replaced_atomically

VIDEO_SUFFIXES = (".mp4", ".gif")
GIF_COLOURS = 64
"""Colours of a GIF's one palette, shared by all its frames: a picture of a few flat colours
needs no more, a shared palette does not flicker, and the file stays small enough for a
README."""
GIF_PALETTE_FRAMES = 10
"""About this many frames, spread over the film, choose a GIF's palette."""


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
            _write_gif(frames, partial, fps=fps)
        else:
            iio.imwrite(
                partial,
                np.stack(frames),
                fps=fps,
                codec="libx264",
                macro_block_size=1,
                plugin="FFMPEG",
            )


def _write_gif(frames: list[np.ndarray], out: Path, *, fps: int) -> None:
    """An animated GIF of ``frames`` with one palette of ``GIF_COLOURS``, without dithering
    (which would make the flat colours shimmer from frame to frame)."""
    sample = np.concatenate(frames[:: max(1, len(frames) // GIF_PALETTE_FRAMES)], axis=0)
    palette = Image.fromarray(sample).quantize(
        GIF_COLOURS, method=Image.Quantize.MEDIANCUT, dither=Image.Dither.NONE
    )
    pictures = [
        Image.fromarray(frame).quantize(palette=palette, dither=Image.Dither.NONE)
        for frame in frames
    ]
    pictures[0].save(
        out, format="GIF", save_all=True, append_images=pictures[1:], duration=1000 / fps, loop=0
    )
