"""A 3D-view draw handler installed once per add-on session, the way every overlay of the
add-on (seams, collision levels, body places) installs its own: added at register, never in
background mode (no window draws there), removed at unregister."""

from __future__ import annotations

from typing import Callable

import bpy


class ViewDrawHandler:
    """`draw` run by the 3D view after its scene (`POST_VIEW`), from `register` to `unregister`."""

    def __init__(self, draw: Callable[[], None]):
        self.draw = draw
        self.handle = None

    def register(self) -> None:
        if bpy.app.background or self.handle is not None:
            return
        self.handle = bpy.types.SpaceView3D.draw_handler_add(self.draw, (), "WINDOW", "POST_VIEW")

    def unregister(self) -> None:
        if self.handle is not None:
            bpy.types.SpaceView3D.draw_handler_remove(self.handle, "WINDOW")
            self.handle = None
