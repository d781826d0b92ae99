"""PNG encoding without extra dependencies, and small thumbnails of rendered frames."""

from __future__ import annotations

import struct
import zlib

import numpy as np

PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"


def encode_png(image: np.ndarray) -> bytes:
    """An 8-bit RGB, RGBA or grey image (H x W [x C], floats in [0, 1] or integers 0-255) as PNG."""
    array = np.asarray(image)
    if array.dtype.kind == "f":
        array = np.clip(array, 0.0, 1.0) * 255.0 + 0.5
    array = np.clip(array, 0, 255).astype(np.uint8)
    if array.ndim == 3 and array.shape[2] == 1:
        array = array[:, :, 0]
    if array.ndim == 2:
        colour_type = 0
    elif array.ndim == 3 and array.shape[2] in (3, 4):
        colour_type = 2 if array.shape[2] == 3 else 6
    else:
        raise ValueError(f"not an image: shape {array.shape}")
    height, width = array.shape[:2]
    if height < 1 or width < 1:
        raise ValueError(f"empty image: shape {array.shape}")
    rows = np.ascontiguousarray(array).reshape(height, -1)
    raw = np.hstack([np.zeros((height, 1), np.uint8), rows]).tobytes()  # filter 0 per row

    def chunk(kind: bytes, data: bytes) -> bytes:
        return (struct.pack(">I", len(data)) + kind + data
                + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF))

    header = struct.pack(">IIBBBBB", width, height, 8, colour_type, 0, 0, 0)
    return (PNG_SIGNATURE + chunk(b"IHDR", header) + chunk(b"IDAT", zlib.compress(raw, 9))
            + chunk(b"IEND", b""))


def thumbnail(image: np.ndarray, max_side: int = 200) -> np.ndarray:
    """``image`` shrunk by an integer stride so that its longer side is at most ``max_side``."""
    array = np.asarray(image)
    stride = max(1, -(-max(array.shape[:2]) // max_side))
    return array[::stride, ::stride]


def pick(count: int, most: int) -> list[int]:
    """At most ``most`` indices spread evenly over ``range(count)``, first and last included."""
    if count <= most:
        return list(range(count))
    return sorted({round(i * (count - 1) / (most - 1)) for i in range(most)})
