"""File handlers: runs end before a file is replaced; older files' settings are carried over.

- `load_pre`: every modal run (the bake, Live) and Live session ends while the old file is
  still loaded. Blender cancels the modal operators later in the load, when the new file's
  data may already be in place, so their `cancel` touches no scene data (`runs.py`).
- `save_pre` / `save_post`: a save during Live writes the pieces as they were before Live
  (`LiveSession.hold_for_save`), and the drape is put back after it.
- `frame_change_post`: with a Fit Map chosen and a bake that kept its maps, the frame's maps are
  written onto the pieces (`fit_map_attrs.show_baked`).
- `load_post`: a file saved before the add-on took gravity from the scene kept its own in
  `Scene.tailor_simulate["gravity"]` (an ID property the panel no longer has); it becomes the
  scene's gravity, once, and the old value is removed.
"""

from __future__ import annotations

import bpy
from bpy.app.handlers import persistent

from . import fit_map_attrs, live, runs

#: The ID property of files from before the scene's gravity was used.
LEGACY_GRAVITY = "gravity"


@persistent
def end_runs(_filepath="") -> None:
    runs.abandon_all()
    live.stop_all()


@persistent
def carry_over_settings(_filepath="") -> None:
    for scene in bpy.data.scenes:
        s = scene.tailor_simulate
        if LEGACY_GRAVITY in s.keys():
            scene.gravity = tuple(s[LEGACY_GRAVITY])
            del s[LEGACY_GRAVITY]


@persistent
def hold_live_for_save(_filepath="") -> None:
    live.hold_all_for_save()


@persistent
def resume_live_after_save(_filepath="") -> None:
    live.resume_all_after_save()


@persistent
def show_baked_fit_maps(scene, _depsgraph=None) -> None:
    fit_map_attrs.show_baked(scene)


_HANDLERS = (
    (bpy.app.handlers.load_pre, end_runs),
    (bpy.app.handlers.load_post, carry_over_settings),
    (bpy.app.handlers.save_pre, hold_live_for_save),
    (bpy.app.handlers.save_post, resume_live_after_save),
    (bpy.app.handlers.frame_change_post, show_baked_fit_maps),
)


def register() -> None:
    for handlers, fn in _HANDLERS:
        if fn not in handlers:
            handlers.append(fn)


def unregister() -> None:
    for handlers, fn in _HANDLERS:
        if fn in handlers:
            handlers.remove(fn)
