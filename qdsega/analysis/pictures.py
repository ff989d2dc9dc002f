"""Pictures written small: a matplotlib figure or a render saved as a palette PNG."""

from __future__ import annotations

import io
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.figure import Figure
from PIL import Image

from qdsega.atomic import replaced_atomically


def figure_pixels(figure: Figure, *, dpi: float | None = None) -> np.ndarray:
    """A matplotlib figure as (height, width, 3) uint8 (at ``dpi``, else the figure's own);
    the figure is closed."""
    buffer = io.BytesIO()
    figure.savefig(buffer, format="png", dpi=dpi or "figure", facecolor="white")
    plt.close(figure)
    return np.asarray(Image.open(buffer).convert("RGB"))


def save_png(
    picture: np.ndarray,
    file: Path,
    *,
    colours: int,
    method: Image.Quantize = Image.Quantize.MAXCOVERAGE,
) -> Path:
    """Write ``picture`` (height, width, 3) uint8 as a PNG of at most ``colours`` colours, a
    fraction of the full PNG's size (``method``: how Pillow chooses them)."""
    file.parent.mkdir(parents=True, exist_ok=True)
    image = Image.fromarray(picture).quantize(colours, method=method)
    with replaced_atomically(file) as partial:
        image.save(partial, format="PNG", optimize=True)
    return file
