"""The 3D view of a GUI test's Blender window, shared by the drivers (`driver.py`,
`live_driver.py`, `bend_gizmo_driver.py`): the view's window, area, region and RegionView3D, a
context override on it, a world point's window pixel, and a key pressed and released there.
Imported inside Blender (the drivers put this folder on `sys.path`)."""

from __future__ import annotations

import bpy


def view3d():
    """(window, area, WINDOW region, RegionView3D) of the 3D view."""
    win = bpy.context.window_manager.windows[0]
    area = next(a for a in win.screen.areas if a.type == "VIEW_3D")
    region = next(r for r in area.regions if r.type == "WINDOW")
    return win, area, region, area.spaces.active.region_3d


def override():
    win, area, region, _ = view3d()
    return bpy.context.temp_override(window=win, area=area, region=region, screen=win.screen)


def to_window(world) -> tuple[int, int]:
    """Window pixel of a world point (event_simulate takes window coordinates)."""
    from bpy_extras import view3d_utils

    _, _, region, rv3d = view3d()
    xy = view3d_utils.location_3d_to_region_2d(region, rv3d, world)
    return int(round(region.x + xy[0])), int(round(region.y + xy[1]))


def key(name, **modifiers):
    """Presses and releases key `name` in the window."""
    win = view3d()[0]
    win.event_simulate(type=name, value="PRESS", **modifiers)
    win.event_simulate(type=name, value="RELEASE", **modifiers)
