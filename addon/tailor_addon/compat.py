"""Small shims between the Blender versions the add-on loads in (3.4 legacy to 5.x extension).

Everything version-dependent lives here so the feature folders read the same everywhere.
(Modules that define Blender classes do not use `from __future__ import annotations`: property
annotations must stay objects, not strings, for the older registration code.)
"""

from __future__ import annotations

import glob
import importlib
import os
import sys
import zipfile

import bpy

VERSION = bpy.app.version
IS_EXTENSION_SYSTEM = VERSION >= (4, 2, 0)
HERE = os.path.dirname(os.path.abspath(__file__))


def ensure_tailor() -> None:
    """Makes the bundled `tailor` wheel importable.

    As an extension (4.2+), Blender installs the manifest's wheels itself and `import tailor`
    just works. As a legacy add-on (3.4 to 4.1, or the folder loaded directly), the wheel in
    `wheels/` is unpacked once into `_vendor/<wheel name>/` beside this file and put on
    `sys.path`."""
    try:
        import tailor  # noqa: F401

        return
    except ImportError:
        pass
    wheels = sorted(glob.glob(os.path.join(HERE, "wheels", "tailor-*.whl")))
    if not wheels:
        raise ImportError(
            "Tailor: the native module `tailor` is missing and no wheel is bundled in "
            f"{os.path.join(HERE, 'wheels')}; build the add-on with `make addon`"
        )
    wheel = wheels[-1]
    name = os.path.splitext(os.path.basename(wheel))[0]
    target = os.path.join(HERE, "_vendor", name)
    try:
        _unpack(wheel, target)
    except OSError:  # a read-only add-on folder: unpack into Blender's user cache instead
        target = os.path.join(bpy.utils.user_resource("SCRIPTS", path="tailor_vendor", create=True), name)
        _unpack(wheel, target)
    if target not in sys.path:
        sys.path.insert(0, target)
    importlib.import_module("tailor")


def _unpack(wheel: str, target: str) -> None:
    if os.path.isdir(os.path.join(target, "tailor")):
        return
    tmp = target + ".partial"
    with zipfile.ZipFile(wheel) as z:
        z.extractall(tmp)
    os.replace(tmp, target)


def _builtin_shader(names: tuple[str, ...], what: str):
    """The first of `names` that this Blender's `gpu.shader.from_builtin` knows (built-in shaders
    lost their '3D_' prefix in 4.0: the newer name is tried first)."""
    import gpu

    for name in names:
        try:
            return gpu.shader.from_builtin(name)
        except (ValueError, TypeError):
            continue
    raise RuntimeError(f"no {what} shader in this Blender")


def polyline_shader():
    """The built-in wide-line shader (uniforms color, viewportSize, lineWidth)."""
    return _builtin_shader(("POLYLINE_UNIFORM_COLOR", "3D_POLYLINE_UNIFORM_COLOR"), "polyline")


def point_shader():
    """The built-in flat-colour shader with a per-vertex colour."""
    return _builtin_shader(("FLAT_COLOR", "3D_FLAT_COLOR"), "flat-colour")


def smooth_colour_shader():
    """The built-in shader with per-vertex colours interpolated across a triangle."""
    return _builtin_shader(("SMOOTH_COLOR", "3D_SMOOTH_COLOR"), "smooth-colour")


#: Options of a path property that takes "//" (relative to the .blend): 4.5 warns on such a value
#: unless the property says so; older versions have no such option.
BLEND_RELATIVE_PATH = {"PATH_SUPPORTS_BLEND_RELATIVE"} if VERSION >= (4, 5, 0) else set()


def move_modifier_first(obj, mod) -> None:
    """Moves `mod` to the top of `obj`'s modifier stack. `ObjectModifiers.move` (Blender 4.x+)
    needs no context; older versions (3.4) only have the operator, given the object."""
    index = list(obj.modifiers).index(mod)
    if index == 0:
        return
    if hasattr(obj.modifiers, "move"):
        obj.modifiers.move(index, 0)
    else:
        move_modifier_by_operator(obj, mod)


def move_modifier_by_operator(obj, mod) -> None:
    """`object.modifier_move_to_index` on `obj` (what 3.4 has; 3.2+ has `temp_override`)."""
    with bpy.context.temp_override(object=obj, active_object=obj):
        bpy.ops.object.modifier_move_to_index(modifier=mod.name, index=0)


def import_menu():
    return bpy.types.TOPBAR_MT_file_import


def export_menu():
    return bpy.types.TOPBAR_MT_file_export
