"""A quick picture of a garment on a body, with no renderer: the body's vertices in grey and the
garment's particles in red, splatted orthographically from the front and from the side (Y up).
Enough to see at a glance whether a garment is on the body, slid down or on the floor."""

from __future__ import annotations

import numpy as np
from PIL import Image, ImageDraw

SCALE = 160  # pixels per metre


def _view(body: np.ndarray, cloth: np.ndarray, axis: int, label: str, top: float) -> Image.Image:
    w, h = int(1.4 * SCALE), int((top + 0.05) * SCALE)
    im = Image.new("RGB", (w, h), (255, 255, 255))
    d = ImageDraw.Draw(im)

    def pixels(p: np.ndarray) -> np.ndarray:
        u = p[:, 0] if axis == 0 else p[:, 2]
        return np.stack([(u + 0.7) * SCALE, (top - p[:, 1]) * SCALE], 1)

    for q in pixels(body[::2]):
        d.point(tuple(q), fill=(185, 185, 185))
    for q in pixels(cloth):
        d.point(tuple(q), fill=(205, 25, 25))
    d.text((4, 4), label, fill=(0, 0, 0))
    return im


def garment_on_body(body: np.ndarray, cloth: np.ndarray, title: str, path: str) -> None:
    """Writes a PNG: front and side views of `cloth` (n, 3) on `body` (m, 3), metres, Y up.
    The cloth is clipped to the frame (a garment that fell far shows as gone)."""
    top = float(body[:, 1].max()) + 0.1
    views = [_view(body, cloth, 0, f"{title} (front)", top), _view(body, cloth, 1, "side", top)]
    sheet = Image.new("RGB", (sum(v.width for v in views), views[0].height), (255, 255, 255))
    x = 0
    for v in views:
        sheet.paste(v, (x, 0))
        x += v.width
    sheet.save(path)
