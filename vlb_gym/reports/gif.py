"""Frames of an episode as an animated GIF (needs Pillow)."""

from __future__ import annotations

import io
from pathlib import Path

import numpy as np

from vlb_gym.core.files import write_atomic


def write_gif(out: Path, frames: list[np.ndarray], render_fps: float, fps: int) -> int:
    """``frames`` (thinned to ``fps``, the last one kept) as an animated GIF at ``out``,
    written atomically; the number of frames in the file."""
    from PIL import Image

    stride = max(1, round(render_fps / fps))
    frames = frames[::stride] + frames[-1:]  # the last state too, whatever the stride
    images = [Image.fromarray(frame) for frame in frames]
    gif = io.BytesIO()
    images[0].save(gif, format="GIF", save_all=True, append_images=images[1:],
                   duration=int(1000 / fps), loop=0)
    write_atomic(out, gif.getvalue())
    with Image.open(gif) as written:  # identical consecutive frames are merged into one
        return written.n_frames
