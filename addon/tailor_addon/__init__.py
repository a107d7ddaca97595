"""Tailor: sew 2D sewing patterns into 3D garments and simulate them on characters.

The Blender side of Tailor (UI only): it converts Blender data to numpy arrays, calls the
native module `tailor` for every computation, and draws. Loaded as an extension (Blender 4.2+,
see blender_manifest.toml, the `tailor` wheel installed by Blender) or as a legacy add-on
(Blender 3.4+, `bl_info` below, the bundled wheel unpacked by `compat.ensure_tailor`).

Layout (bdk_addon style): one folder per feature, each with `properties.py`, `operators.py`,
`ui.py`, registered in workflow order; `core/` is the bpy-free half (tested without Blender);
`scene_data.py` reads the scene into the module's terms (`build_garment`); `reporting.py` turns
errors into status-bar reports. The data model is described in docs/addon.md.
"""

bl_info = {
    "name": "Tailor",
    "author": "Tailor developers",
    "version": (0, 1, 0),
    "blender": (3, 4, 0),
    "location": "View3D > Sidebar > Tailor; File > Import > Sewing Pattern",
    "description": "Sew 2D sewing patterns into 3D garments and simulate them on characters",
    "category": "Import-Export",
}

# Nothing Blender-specific is imported at module level, so that `tailor_addon.core` (bpy-free)
# imports in plain Python too.


def _features():
    """The feature packages in registration order (seams first: they own `Scene.tailor`, which
    the pattern importer fills). Panels are ordered by their `bl_order`."""
    from . import arrange, bend, menu, paint, patterns, preferences, seams, simulate

    return (preferences, seams, patterns, arrange, bend, paint, simulate, menu)


def register() -> None:
    from . import compat

    compat.ensure_tailor()
    import bpy

    for feature in _features():
        for cls in feature.classes:
            bpy.utils.register_class(cls)
        feature.register()


def unregister() -> None:
    import bpy

    for feature in reversed(_features()):
        feature.unregister()
        for cls in reversed(feature.classes):
            bpy.utils.unregister_class(cls)
