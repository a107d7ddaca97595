"""Export Garment Animation: the baked garment welded along its seams, as one animated object,
written with Blender's own Alembic or USD exporter.

The pieces' caches crack along every seam once shaded (each side of a seam is its own row of
vertices), so studios are handed the welded garment (issue 24: the welded garment is the
default for every format). The garment is welded once (`tailor.weld` through `core.welded`, as
Export Welded Garment does, UVs and materials kept) and each frame of the scene's range, as the
pieces play it (their Mesh Cache, or the joined garment object's), is carried over
(`WeldedMesh.apply`) into a PC2 cache beside the bake's, named after the welded object and
played on it by a Mesh Cache modifier: the scene shows what was written. Blender's exporter then writes the object over
the range (Alembic: `wm.alembic_export`; USD: `wm.usd_export`). Per Piece writes the piece
objects instead, as the bake plays them (each its own mesh, as `tailor simulate --per-piece`),
and adds nothing to the scene.

A USD file also gets the garment's thickness (the distance it was simulated keeping from the
body) as the constant primvar `tailor_thickness` on its meshes, as `tailor simulate --usd`
writes it (`tailor.usd.set_thickness`, through the `pxr` Blender bundles), for a render-time
shell that stays outside the body.
"""

from __future__ import annotations

import os

import bpy
import numpy as np
from bpy.props import BoolProperty, EnumProperty, StringProperty

from tailor import bake

from .. import compat
from ..core import AddonError, welded
from ..reporting import reports_errors
from . import job as bake_job
from .export_welded import (
    alone_selected,
    garment_positions,
    invoke_exporter,
    output_path,
    remove_object,
    removed_on_failure,
    scene_pieces,
    welded_object,
)

FORMATS = [
    ("ABC", "Alembic", "Alembic (.abc), Blender's exporter: Houdini, Maya, Unreal and Blender read it"),
    ("USD", "USD", "Universal Scene Description (.usdc), Blender's exporter"),
    ("NONE", "Object Only", "Only add the animated welded object to the scene"),
]
EXTENSIONS = {"ABC": ".abc", "USD": ".usdc"}


def welded_frames(scene, objects, garment_name: str, w, start: int, end: int) -> np.ndarray:
    """The welded points of every frame from `start` to `end` ((frames, k, 3) float32), as the
    pieces play them; the scene's frame is restored."""
    frame = scene.frame_current
    try:
        out = []
        for f in range(start, end + 1):
            scene.frame_set(f)
            out.append(np.asarray(w.apply(garment_positions(scene, objects, garment_name)), np.float32))
    finally:
        scene.frame_set(frame)
    return np.stack(out)


def play(obj, path: str, start: int) -> None:
    """A Mesh Cache modifier on `obj` playing the PC2 at `path` from frame `start`."""
    mod = obj.modifiers.new(bake_job.MODIFIER, "MESH_CACHE")
    compat.move_modifier_first(obj, mod)
    mod.cache_format = "PC2"
    mod.filepath = bpy.path.relpath(path) if bpy.data.filepath else path
    mod.play_mode = "SCENE"
    mod.time_mode = "FRAME"
    mod.frame_start = float(start)


def write_file(context, objs, fmt: str, path: str, start: int, end: int) -> None:
    """Writes `objs` alone over `start`-`end` with Blender's Alembic or USD exporter (USD: with
    the scene's thickness on every mesh)."""
    with alone_selected(context, *objs):
        if fmt == "ABC":
            bpy.ops.wm.alembic_export(filepath=path, start=start, end=end, selected=True, uvs=True,
                                      face_sets=True)
        else:
            scene = context.scene
            keep = scene.frame_start, scene.frame_end
            scene.frame_start, scene.frame_end = start, end  # USD exports the scene's range
            try:
                bpy.ops.wm.usd_export(filepath=path, selected_objects_only=True, export_animation=True,
                                      export_uvmaps=True, export_materials=True)
            finally:
                scene.frame_start, scene.frame_end = keep
            mark_thickness(path, scene.tailor_simulate.thickness)


def mark_thickness(path: str, thickness: float) -> None:
    """The garment's thickness on the USD file's meshes (`tailor.usd.set_thickness`)."""
    from tailor import usd

    if not usd.set_thickness(path, float(thickness)):
        raise AddonError(f"{os.path.basename(path)}: Blender's USD exporter wrote no mesh",
                         "Check that the garment's objects are visible and enabled for export")


def played_pieces(objects) -> list:
    """The piece objects when each plays the bake (its Mesh Cache); refused otherwise."""
    silent = [o.name for o in objects if o.modifiers.get(bake_job.MODIFIER) is None]
    if silent:
        raise AddonError(f"pieces {', '.join(silent[:4])}{' ...' if len(silent) > 4 else ''} do not play the bake",
                         "Bake the garment piece by piece (the default), or turn Per Piece off")
    return list(objects)


class TAILOR_OT_export_animation(bpy.types.Operator):
    bl_idname = "tailor.export_animation"
    bl_label = "Export Garment Animation"
    bl_description = (
        "The baked garment over the bake's frame range as one animated mesh, welded along its seams (UVs and "
        "materials kept), written as Alembic or USD with Blender's exporter"
    )
    # It adds the animated welded object to the scene (a cache beside the bake's plays it):
    # an undo step, as Export Welded Garment.
    bl_options = {"REGISTER", "UNDO"}

    garment: StringProperty(name="Garment", description="Only this garment's pieces (empty: the Simulate panel's)")
    export_format: EnumProperty(name="Format", items=FORMATS, default="ABC")
    per_piece: BoolProperty(
        name="Per Piece", default=False,
        description="Write the piece objects as the bake plays them, each its own mesh, instead of the garment welded "
                    "along its seams (the default: one surface, no crack along a seam)",
    )
    filepath: StringProperty(name="File", subtype="FILE_PATH", description="Where to write the file")
    filter_glob: StringProperty(default="*.abc;*.usdc;*.usd", options={"HIDDEN"})

    def invoke(self, context, event):
        return invoke_exporter(self, context, "garment", EXTENSIONS)

    @reports_errors("Exporting the garment animation")
    def execute(self, context):
        scene = context.scene
        objects, name, garment_name = scene_pieces(scene, self.garment)
        if not scene.tailor_simulate.baked_frames:
            raise AddonError("the garment is not baked", "Bake it first (Simulate panel > Bake)")
        path = ""
        if self.export_format != "NONE":
            path = output_path(self.filepath, EXTENSIONS[self.export_format], "Format: Object Only")
        start, end = bake_job.frame_range(scene)
        if self.per_piece:
            if not path:
                raise AddonError("Per Piece with Object Only: the pieces already play the bake",
                                 "Choose Alembic or USD, or turn Per Piece off")
            pieces = played_pieces(objects)
            write_file(context, pieces, self.export_format, path, start, end)
            self.report({"INFO"}, f"{len(pieces)} pieces: frames {start}-{end}; wrote {os.path.basename(path)}")
            return {"FINISHED"}
        folder = bake_job.cache_folder(scene)
        # The frames are read before the scene changes; the weld is made where the pieces stand.
        obj, w = welded_object(scene, objects, name, garment_name, "animated")
        try:
            frames = welded_frames(scene, objects, garment_name, w, start, end)
            os.makedirs(folder, exist_ok=True)
            # Named after the object (unique in the file): a second export gets a cache of its own.
            cache = os.path.join(folder, f"{bpy.path.clean_name(obj.name)}.pc2")
            bake.write_pc2_atomic(cache, frames, start_frame=start, sample_rate=1.0)
        except Exception:
            remove_object(obj)
            raise
        play(obj, cache, start)
        if path:
            removed_on_failure(obj, lambda: write_file(context, [obj], self.export_format, path, start, end))
        where = f"; wrote {os.path.basename(path)}" if path else ""
        self.report({"INFO"}, f"{obj.name}: frames {start}-{end}, {welded.summary(w)}{where}")
        return {"FINISHED"}


classes = (TAILOR_OT_export_animation,)
