"""The add-on's preferences (Edit > Preferences > Add-ons > Tailor): what belongs to the machine
or the studio rather than to one .blend: the solver backend, the default cache folder and the
solver's CPU threads. A scene's Simulate settings use them unless set otherwise there (Backend
*Preferences*, an empty Cache Folder), in the bake and in Live alike.

(No `from __future__ import annotations`: property annotations must stay objects for the older
registration code, see compat.py.)
"""

import bpy
from bpy.props import EnumProperty, IntProperty, StringProperty

from .compat import BLEND_RELATIVE_PATH

#: The solver backends (`Garment.build_simulation(backend=...)`, lower-cased).
BACKENDS = (
    ("AUTO", "Auto", "The GPU on a discrete graphics card from 10,000 particles up (where it was measured "
     "faster), else the CPU", 0),
    ("CPU", "CPU", "Multi-threaded CPU solver", 1),
    ("GPU", "GPU", "wgpu compute (Vulkan, Metal, DX12)", 2),
)
DEFAULT_CACHE_DIR = "//tailor_cache"


class TailorPreferences(bpy.types.AddonPreferences):
    # The add-on's module: `bl_ext.<repo>.tailor_addon` as an extension, `tailor_addon` legacy.
    bl_idname = __package__

    backend: EnumProperty(name="Backend", description="The solver backend of scenes that do not choose one",
                          items=BACKENDS, default="AUTO")
    cache_dir: StringProperty(
        name="Cache Folder", description="Where bakes write their PC2 caches when the scene names no folder "
        "(// = beside the .blend)", default=DEFAULT_CACHE_DIR, subtype="DIR_PATH", options=BLEND_RELATIVE_PATH,
    )

    threads: IntProperty(
        name="Solver Threads", description="CPU threads of a simulation (0: one per core); results do not "
        "depend on it, so a machine can be shared with other work", default=0, min=0, soft_max=64,
    )

    def draw(self, context):
        layout = self.layout
        layout.prop(self, "backend")
        layout.prop(self, "cache_dir")
        layout.prop(self, "threads")


def current():
    """The preferences, or None where the add-on is not enabled under its package's name (its
    modules imported by a script): then the defaults above apply."""
    addon = bpy.context.preferences.addons.get(__package__)
    return addon.preferences if addon is not None else None


def backend(scene) -> str:
    """The backend a scene's simulation runs on: its own, or the preferences'."""
    chosen = scene.tailor_simulate.backend
    if chosen == "PREFERENCES":
        prefs = current()
        chosen = prefs.backend if prefs is not None else "AUTO"
    return chosen.lower()


def threads() -> int | None:
    """The solver's CPU threads (`Simulation.set_threads`), None: one per core."""
    prefs = current()
    return prefs.threads if prefs is not None and prefs.threads > 0 else None


def cache_dir(scene) -> str:
    """A scene's cache folder as set (relative paths with //): its own, or the preferences'."""
    own = scene.tailor_simulate.cache_dir
    if own:
        return own
    prefs = current()
    return prefs.cache_dir if prefs is not None and prefs.cache_dir else DEFAULT_CACHE_DIR


classes = (TailorPreferences,)


def register() -> None:
    pass


def unregister() -> None:
    pass
