"""File handlers: runs end before a file is replaced.

- `load_pre`: every modal run (the bake, Live) and Live session ends while the old file is
  still loaded. Blender cancels the modal operators later in the load, when the new file's
  data may already be in place, so their `cancel` touches no scene data (`runs.py`).
"""

from __future__ import annotations

import bpy
from bpy.app.handlers import persistent

from . import live, runs

@persistent
def end_runs(_filepath="") -> None:
    runs.abandon_all()
    live.stop_all()


_HANDLERS = ((bpy.app.handlers.load_pre, end_runs),)


def register() -> None:
    for handlers, fn in _HANDLERS:
        if fn not in handlers:
            handlers.append(fn)


def unregister() -> None:
    for handlers, fn in _HANDLERS:
        if fn in handlers:
            handlers.remove(fn)
