"""The collider body's places drawn in the viewport while Show Places is on: each place's axis
as a line from its origin along its length, the torso's front and back facings as short
arrows. The places are the last ones found (Arrange on Body, or turning Show Places on); the
draw handler (not installed in background mode) only draws them."""

from __future__ import annotations

import bpy
import numpy as np

from ..view_draw import ViewDrawHandler

from ..core.arrange import axis_lines


#: Colours by place (torso, waist, neck and head, arms, legs).
_COLOURS = {
    "torso_front": (1.0, 0.55, 0.1, 1.0),
    "torso_back": (1.0, 0.55, 0.1, 1.0),
    "waist": (0.9, 0.9, 0.2, 1.0),
    "neck": (1.0, 0.4, 0.8, 1.0),
    "head": (1.0, 0.4, 0.8, 1.0),
    "left_arm": (0.2, 0.8, 1.0, 1.0),
    "right_arm": (0.2, 0.8, 1.0, 1.0),
    "left_leg": (0.4, 1.0, 0.4, 1.0),
    "right_leg": (0.4, 1.0, 0.4, 1.0),
}


def place_lines(places) -> list[tuple[tuple[float, float, float, float], np.ndarray]]:
    """(colour, (2k, 3) segments) per place: its axis, and its facing (0.15 m) from its origin."""
    out = []
    axes = axis_lines(places)
    for p in places:
        o = np.asarray(p["origin"], np.float32)
        facing = np.array([o, o + 0.15 * np.asarray(p["facing"], np.float32)], np.float32)
        segs = np.concatenate([axes[p["name"]], facing]) if p["name"] == "torso_front" else axes[p["name"]]
        out.append((_COLOURS.get(p["name"], (1.0, 1.0, 1.0, 1.0)), segs))
    return out


def on_toggle(wm, context) -> None:
    """Show Places turned on: find the places unless already found (an error: nothing drawn)."""
    from . import operators
    from ..core import AddonError

    if wm.tailor_show_places and not operators.last_places:
        import tailor

        try:
            operators.places_of(context.scene)
        except (AddonError, tailor.TailorError):
            pass
    from ..ui_common import redraw_view3d

    redraw_view3d(context)


def _draw() -> None:
    import gpu
    from gpu_extras.batch import batch_for_shader

    from ..compat import polyline_shader
    from . import operators

    context = bpy.context
    if not context.window_manager.tailor_show_places or context.region is None:
        return
    places = operators.last_places.get("places")
    if not places or operators.last_places.get("collider") not in context.scene.objects:
        return
    shader = polyline_shader()
    gpu.state.depth_test_set("NONE")
    gpu.state.blend_set("ALPHA")
    shader.bind()
    shader.uniform_float("viewportSize", (context.region.width, context.region.height))
    shader.uniform_float("lineWidth", 3.0)
    for colour, segs in place_lines(places):
        batch = batch_for_shader(shader, "LINES", {"pos": segs})
        shader.uniform_float("color", colour)
        batch.draw(shader)
    gpu.state.blend_set("NONE")


_HANDLER = ViewDrawHandler(_draw)


def register() -> None:
    _HANDLER.register()


def unregister() -> None:
    _HANDLER.unregister()
