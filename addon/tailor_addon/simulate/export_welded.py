"""Export Welded Garment: the garment's pieces as one mesh object at the current frame.

Positions are the evaluated pieces (so a baked frame, played by the Mesh Cache modifier, is
welded as it looks), or the joined "(baked)" object of a per-garment cache; the weld is
`tailor.weld` through `core.welded`. UV maps present on every piece carry over per corner, and
the pieces' materials face by face (one slot per distinct material, in the order first met).
The object is optionally written with Blender's own OBJ or glTF exporter.
"""

from __future__ import annotations

import os
from contextlib import contextmanager

import bpy
import numpy as np
from bpy.props import EnumProperty, StringProperty

from .. import scene_data
from ..core import AddonError, welded
from ..reporting import reports_errors
from .gather import evaluated_positions
from .job import MODIFIER

FORMATS = [
    ("NONE", "Object Only", "Only add the welded mesh object to the scene"),
    ("OBJ", "OBJ", "Also write it as Wavefront OBJ (Blender's exporter)"),
    ("GLB", "glTF Binary", "Also write it as glTF binary .glb (Blender's exporter)"),
]
EXTENSIONS = {"OBJ": ".obj", "GLB": ".glb"}


def garment_positions(scene, objects, garment_name: str) -> np.ndarray:
    """World positions of every particle at the current frame: the joined per-garment cache
    object when it plays one, else each piece evaluated with its modifiers."""
    dg = bpy.context.evaluated_depsgraph_get()
    baked = bpy.data.objects.get(f"{garment_name} (baked)")
    total = sum(len(o.data.vertices) for o in objects)
    if baked is not None and baked.modifiers.get(MODIFIER) is not None and len(baked.data.vertices) == total:
        return evaluated_positions(baked, dg)
    parts = []
    for o in objects:
        p = evaluated_positions(o, dg)
        if len(p) != len(o.data.vertices):
            raise AddonError(
                f"piece '{o.name}' has {len(o.data.vertices)} vertices but {len(p)} after its modifiers",
                "Disable the modifiers that change its vertex count (a Mesh Cache is fine)",
            )
        parts.append(p)
    return np.concatenate(parts)


def corner_uvs(objects, garment) -> dict[str, np.ndarray]:
    """The UV maps every piece has, per corner in garment order ((3 × triangles, 2) each).
    Refuses a piece whose faces no longer are its pattern's triangles."""
    names = set.intersection(*(set(uv.name for uv in o.data.uv_layers) for o in objects))
    out: dict[str, list[np.ndarray]] = {n: [] for n in sorted(names)}
    first = np.concatenate([[0], np.cumsum([len(m.triangles) for m in garment.meshes])])
    for i, o in enumerate(objects):
        me = o.data
        loops = np.empty(len(me.loops), np.int32)
        me.loops.foreach_get("vertex_index", loops)
        own = garment.triangles[first[i] : first[i + 1]] - int(garment.offsets[i])
        if len(me.polygons) != len(own) or len(loops) != own.size or not np.array_equal(loops, own.reshape(-1)):
            raise AddonError(
                f"piece '{o.name}': its faces are no longer its pattern's triangles",
                "Set its resolution again (Patterns panel) to rebuild it",
            )
        for n in out:
            uv = np.empty(len(me.loops) * 2, np.float32)
            me.uv_layers[n].data.foreach_get("uv", uv)
            out[n].append(uv.reshape(-1, 2))
    return {n: np.concatenate(v) for n, v in out.items()}


def corner_materials(objects) -> tuple[list, np.ndarray]:
    """The pieces' materials, each once in the order first met (None for a face with none), and
    per corner in garment order the index of its face's material in that list ((3 × triangles,
    1), as float for `welded_corner_values`). The faces are the pattern's triangles
    (`corner_uvs` checks)."""
    materials: list = []
    parts = []
    for o in objects:
        me = o.data
        slots = [s.material for s in o.material_slots]
        index = np.zeros(len(me.polygons), np.int32)
        me.polygons.foreach_get("material_index", index)
        local = []
        for m in slots or [None]:
            if m not in materials:
                materials.append(m)
            local.append(materials.index(m))
        per_face = np.asarray(local, np.float32)[np.clip(index, 0, len(local) - 1)]
        parts.append(np.repeat(per_face, 3))
    return materials, np.concatenate(parts).reshape(-1, 1) if parts else np.zeros((0, 1), np.float32)


def assign_materials(me, materials: list, corner_index: np.ndarray) -> None:
    """Slots for `materials` on `me` and each face's index from its corners' (a welded face's
    corners all come from one piece's face)."""
    if all(m is None for m in materials):
        return
    for m in materials:
        me.materials.append(m)
    face = np.rint(np.asarray(corner_index, np.float32).reshape(-1, 3).mean(axis=1)).astype(np.int32)
    me.polygons.foreach_set("material_index", face)


def new_mesh_object(scene, name: str, w, uvs: dict[str, np.ndarray], materials=None, corner_index=None):
    me = bpy.data.meshes.new(name)
    co, tris = np.asarray(w.positions, np.float32), np.asarray(w.triangles, np.int32)
    me.vertices.add(len(co))
    me.vertices.foreach_set("co", co.reshape(-1))
    me.loops.add(tris.size)
    me.loops.foreach_set("vertex_index", tris.reshape(-1))
    me.polygons.add(len(tris))
    me.polygons.foreach_set("loop_start", np.arange(0, tris.size, 3, dtype=np.int32))
    if bpy.app.version < (4, 0, 0):
        me.polygons.foreach_set("loop_total", np.full(len(tris), 3, np.int32))
    me.update(calc_edges=True)
    for n, values in uvs.items():
        layer = me.uv_layers.new(name=n)
        layer.data.foreach_set("uv", np.ascontiguousarray(values, np.float32).reshape(-1))
    if materials is not None:
        assign_materials(me, materials, corner_index)
    me.validate()
    me.update()
    obj = bpy.data.objects.new(name, me)
    scene.collection.objects.link(obj)
    return obj


@contextmanager
def alone_selected(context, *objs):
    """`objs` alone selected (the first active) while an exporter writes them (selection restored)."""
    selected = [o for o in context.view_layer.objects if o.select_get()]
    active = context.view_layer.objects.active
    for o in selected:
        o.select_set(False)
    for o in objs:
        o.select_set(True)
    context.view_layer.objects.active = objs[0]
    try:
        yield
    finally:
        for o in objs:
            o.select_set(False)
        for o in selected:
            o.select_set(True)
        context.view_layer.objects.active = active


def write_file(context, obj, fmt: str, path: str) -> None:
    """Writes `obj` alone with Blender's OBJ or glTF exporter."""
    with alone_selected(context, obj):
        if fmt == "OBJ":
            bpy.ops.wm.obj_export(
                filepath=path, export_selected_objects=True, export_uv=True,
                export_materials=len(obj.data.materials) > 0,
            )
        else:
            if not hasattr(bpy.ops.export_scene, "gltf"):
                raise AddonError("Blender's glTF exporter is not enabled", "Enable the glTF 2.0 add-on, or export OBJ")
            bpy.ops.export_scene.gltf(filepath=path, export_format="GLB", use_selection=True)


def default_filepath(suffix: str, ext: str) -> str:
    """Beside the .blend: `<blend>_<suffix><ext>` (or `garment_...` for an unsaved file)."""
    stem = os.path.splitext(bpy.data.filepath)[0] if bpy.data.filepath else "garment"
    return f"{stem}_{suffix}{ext}"


def invoke_exporter(op, context, suffix: str, extensions: dict[str, str]):
    """An export operator's `invoke`: straight to `execute` without a file (`NONE`), else the
    file browser, opened on `default_filepath(suffix, ...)` when no path is set."""
    if op.export_format == "NONE":
        return op.execute(context)
    if not op.filepath:
        op.filepath = default_filepath(suffix, extensions[op.export_format])
    context.window_manager.fileselect_add(op)
    return {"RUNNING_MODAL"}


def output_path(filepath: str, ext: str, none_choice: str) -> str:
    """The file an exporter writes: `filepath` made absolute with `ext`, in an existing folder."""
    if not filepath:
        raise AddonError("no file to write", f"Choose a file, or choose {none_choice}")
    path = bpy.path.ensure_ext(bpy.path.abspath(filepath), ext)
    if not os.path.isdir(os.path.dirname(path) or "."):
        raise AddonError(f"the folder of {path} does not exist", "Choose an existing folder")
    return path


def scene_pieces(scene, garment: str):
    """The pieces of `garment` (empty: the Simulate panel's garment) and the garment's name."""
    name = garment or scene.tailor_simulate.garment or None
    objects = scene_data.piece_objects(scene, name)
    if not objects:
        raise AddonError("the scene has no garment pieces", "Import a pattern first")
    return objects, name, name or (objects[0].tailor_piece.garment or "garment")


def welded_object(scene, objects, name, garment_name: str, label: str):
    """The garment welded where its pieces stand now, as a new object `<garment> (<label>)` with
    the pieces' UVs and materials; returns the object and the weld (`tailor.WeldedMesh`)."""
    g = scene_data.build_garment(scene, name)
    w = welded.weld(g, garment_positions(scene, objects, garment_name))
    uvs = {n: welded.welded_corner_values(w, v) for n, v in corner_uvs(objects, g).items()}
    materials, corner_index = corner_materials(objects)
    corner_index = welded.welded_corner_values(w, corner_index)
    return new_mesh_object(scene, f"{garment_name} ({label})", w, uvs, materials, corner_index), w


def remove_object(obj) -> None:
    """Removes `obj` (just added) and its mesh."""
    me = obj.data
    bpy.data.objects.remove(obj)
    bpy.data.meshes.remove(me)


def removed_on_failure(obj, write) -> None:
    """Runs `write()`; if it fails, `obj` (just added) and its mesh are removed first."""
    try:
        write()
    except Exception:
        remove_object(obj)
        raise


class TAILOR_OT_export_welded(bpy.types.Operator):
    bl_idname = "tailor.export_welded"
    bl_label = "Export Welded Garment"
    bl_description = (
        "Add the garment as one mesh at the current frame (pieces merged along their seams, unequal seams "
        "split so the seam is watertight, UVs and materials kept), and optionally write it as OBJ or glTF"
    )
    bl_options = {"REGISTER", "UNDO"}

    garment: StringProperty(name="Garment", description="Only this garment's pieces (empty: the Simulate panel's)")
    export_format: EnumProperty(name="Write", items=FORMATS, default="NONE")
    filepath: StringProperty(name="File", subtype="FILE_PATH", description="Where to write the OBJ or glTF file")
    filter_glob: StringProperty(default="*.obj;*.glb", options={"HIDDEN"})

    def invoke(self, context, event):
        return invoke_exporter(self, context, "welded", EXTENSIONS)

    @reports_errors("Exporting the welded garment")
    def execute(self, context):
        scene = context.scene
        objects, name, garment_name = scene_pieces(scene, self.garment)
        path = ""
        if self.export_format != "NONE":
            path = output_path(self.filepath, EXTENSIONS[self.export_format], "Write: Object Only")
        # Everything is computed before the scene changes.
        obj, w = welded_object(scene, objects, name, garment_name, "welded")
        if path:
            removed_on_failure(obj, lambda: write_file(context, obj, self.export_format, path))
        where = f"; wrote {os.path.basename(path)}" if path else ""
        self.report({"INFO"}, f"{obj.name}: {welded.summary(w)}{where}")
        return {"FINISHED"}


classes = (TAILOR_OT_export_welded,)
