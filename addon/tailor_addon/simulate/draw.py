"""Live mode's viewport overlay: frames per second, seam gap, penetrations, strain."""

from __future__ import annotations

import bpy

from . import live

_handle = None


def overlay_lines(stats: dict) -> list[str]:
    return [
        f"Tailor Live  {stats['fps']:.1f} fps  (solve {stats['solve_ms']:.0f} ms)",
        f"seam gap {stats['seam_gap_mm']:.2f} mm",
        f"penetrations {stats['penetrations']}  (max {stats['penetration_mm']:.2f} mm)",
        f"strain max {stats['strain']:.3f}",
    ]


def _draw() -> None:
    import blf

    context = bpy.context
    scene = context.scene
    session = live.SESSIONS.get(scene.name) if scene is not None else None
    if session is None or not scene.tailor_simulate.show_overlay:
        return
    font = 0
    blf.size(font, 14)
    blf.color(font, 1.0, 1.0, 1.0, 0.9)
    y = 60
    for line in reversed(overlay_lines(session.stats())):
        blf.position(font, 20, y, 0)
        blf.draw(font, line)
        y += 18


def add() -> None:
    global _handle
    if _handle is None:
        _handle = bpy.types.SpaceView3D.draw_handler_add(_draw, (), "WINDOW", "POST_PIXEL")


def remove() -> None:
    global _handle
    if _handle is not None:
        bpy.types.SpaceView3D.draw_handler_remove(_handle, "WINDOW")
        _handle = None
