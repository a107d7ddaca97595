"""Seam operators: create from picked contour positions, flip, rename, delete, re-check.

Every operator's exec path takes plain properties (object names, contour positions), so
scripts, tests and the interactive tools (manual picking, hover suggestion) share it: a modal
tool ends by calling `bpy.ops.tailor.seam_add(...)` with what the artist picked.
"""

import math

import bpy
from bpy.props import BoolProperty, EnumProperty, FloatProperty, FloatVectorProperty, IntProperty, StringProperty

import tailor

from .. import scene_data
from ..core import AddonError
from ..core import mesh_of
from ..core.garment import SeamData, resolve
from ..reporting import reports_errors
from .properties import MODE_ITEMS
from .store import add_seam_item, store_seam_counts

PATH_ITEMS = [
    ("CCW", "Counter-Clockwise", "Walk the contour counter-clockwise from start to end"),
    ("CW", "Clockwise", "Walk the contour clockwise from start to end"),
    ("SHORTEST", "Shortest", "The shorter way round from start to end (the manual tool's step 3)"),
]


def piece_object(name: str, label: str):
    obj = bpy.data.objects.get(name)
    if not scene_data.is_piece(obj):
        raise AddonError(f"{label}: no garment piece named '{name}'", "Pass the name of an imported piece object")
    return obj


def object_mesh(obj) -> tailor.PieceMesh:
    return mesh_of(obj.tailor_piece)


def contour_path(mesh: tailor.PieceMesh, start: int, end: int, how: str, label: str, count: int = 0):
    """The contour path from position `start` to `end` walked `how`; with `end < 0`, the
    `count`-vertex path from `start` in that direction (step 5 of the manual tool)."""
    n = len(mesh.contour)
    for what, p in (("start", start), ("end", end)):
        if p >= n or (what == "start" and p < 0):
            raise AddonError(
                f"{label} {what} is contour position {p} but the piece has {n} contour vertices",
                "Pick positions on the piece's contour",
            )
    if end < 0:
        if how == "SHORTEST" or count < 1:
            raise AddonError(f"{label} needs an end position", "Give its end, or walk CCW/CW with side A's count")
        ccw, cw = tailor.candidate_paths(mesh, start, count)
        return ccw if how == "CCW" else cw
    if how == "SHORTEST":
        return tailor.shortest_path(mesh, start, end)
    steps = (end - start) % n if how == "CCW" else (start - end) % n
    ccw, cw = tailor.candidate_paths(mesh, start, steps + 1)
    return ccw if how == "CCW" else cw


def unique_seam_name(scene, base: str) -> str:
    names = {s.name for s in scene.tailor.seams}
    if base not in names:
        return base
    k = 1
    while f"{base}.{k:03d}" in names:
        k += 1
    return f"{base}.{k:03d}"


def seam_at(scene, index: int):
    seams = scene.tailor.seams
    i = scene.tailor.seam_index if index < 0 else index
    if not 0 <= i < len(seams):
        raise AddonError(f"there is no seam {i} (the scene has {len(seams)})", "Select a seam in the Seams panel")
    return i, seams[i]


class SeamAddProperties:
    """Add Seam's properties and exec path; the interactive tools (`modal_pick.py`,
    `modal_suggest.py`) share them, so their redo panel is this one and their commit is this
    `execute`."""

    name: StringProperty(name="Name", default="Seam")
    piece_a: StringProperty(name="Piece A", description="Name of side A's piece object")
    a_start: IntProperty(name="a1", description="Contour position of side A's first vertex", min=0)
    a_end: IntProperty(name="an", description="Contour position of side A's last vertex", min=0)
    a_direction: EnumProperty(name="A Walk", items=PATH_ITEMS, default="SHORTEST")
    piece_b: StringProperty(name="Piece B", description="Name of side B's piece object")
    b_start: IntProperty(name="b1", description="Contour position of side B's first vertex", min=0)
    b_end: IntProperty(
        name="bn",
        description="Contour position of side B's last vertex; -1: as many vertices as side A, walking B Walk",
        default=-1,
        min=-1,
    )
    b_direction: EnumProperty(name="B Walk", items=PATH_ITEMS, default="CCW")
    mode: EnumProperty(name="Mode", items=MODE_ITEMS, default="EQUAL")
    stiffness: FloatProperty(
        name="Stiffness", description="Factor on the solver's seam stiffness", default=1.0, min=0.0
    )

    @reports_errors("Adding the seam")
    def execute(self, context):
        scene = context.scene
        obj_a, obj_b = piece_object(self.piece_a, "side A"), piece_object(self.piece_b, "side B")
        ma, mb = object_mesh(obj_a), object_mesh(obj_b)
        path_a = contour_path(ma, self.a_start, self.a_end, self.a_direction, "side A")
        path_b = contour_path(mb, self.b_start, self.b_end, self.b_direction, "side B", count=len(path_a))
        objects = [obj_a] if obj_a == obj_b else [obj_a, obj_b]
        ib = 0 if obj_a == obj_b else 1
        name = unique_seam_name(scene, self.name or "Seam")
        mode = scene_data.MODES[self.mode]
        seam = SeamData.from_tailor(tailor.Seam.from_paths(name, 0, ma, path_a, ib, mb, path_b, mode))
        seam.stiffness = self.stiffness
        r = resolve(seam, [ma] if ib == 0 else [ma, mb])
        add_seam_item(scene, seam, objects, r)
        self.report({"INFO"}, f"Seam '{name}': {len(r['a_vertices'])} + {len(r['b_vertices'])} vertices, {mode}")
        return {"FINISHED"}


def suggested_segment(obj, rest_point, corner_angle: float) -> tailor.ContourPath:
    """The corner-delimited contour run of piece `obj` nearest `rest_point` (rest frame,
    metres), corners being contour angles under `corner_angle` radians: what the automatic
    suggestion lights up under the cursor."""
    mesh = object_mesh(obj)
    corners = tailor.find_corners(mesh, math.degrees(corner_angle))
    if len(corners) < 2:
        raise AddonError(
            f"piece '{obj.name}' has fewer than two corners under {math.degrees(corner_angle):.0f}°",
            "Raise the corner angle in the Seams panel",
        )
    return tailor.nearest_corner_segment(mesh, corners, (float(rest_point[0]), float(rest_point[1])))


def reversed_path(path: tailor.ContourPath) -> tailor.ContourPath:
    return tailor.ContourPath(list(reversed(path.positions)), "cw" if path.direction == "ccw" else "ccw")


class TAILOR_OT_seam_add_segments(bpy.types.Operator):
    bl_idname = "tailor.seam_add_segments"
    bl_label = "Add Seam Between Segments"
    bl_description = (
        "Sew the corner-to-corner contour segment of piece A nearest a point to the one of piece B nearest "
        "another point (the automatic suggestion); unequal pairing when their vertex counts differ"
    )
    bl_options = {"REGISTER", "UNDO"}

    name: StringProperty(name="Name", default="Seam")
    piece_a: StringProperty(name="Piece A", description="Name of side A's piece object")
    a_point: FloatVectorProperty(name="A Point", size=2, description="A point near side A (piece A's rest frame)")
    piece_b: StringProperty(name="Piece B", description="Name of side B's piece object")
    b_point: FloatVectorProperty(name="B Point", size=2, description="A point near side B (piece B's rest frame)")
    corner_angle: FloatProperty(
        name="Corner Angle",
        description="Contour angles under this are corners; 0: the scene's setting",
        subtype="ANGLE",
        default=0.0,
        min=0.0,
        max=math.pi,
    )
    reverse_b: BoolProperty(
        name="Reverse B", description="Walk side B against side A (two panels facing each other)", default=True
    )

    @reports_errors("Adding the suggested seam")
    def execute(self, context):
        scene = context.scene
        obj_a, obj_b = piece_object(self.piece_a, "side A"), piece_object(self.piece_b, "side B")
        angle = self.corner_angle or scene.tailor.corner_angle
        path_a = suggested_segment(obj_a, self.a_point, angle)
        path_b = suggested_segment(obj_b, self.b_point, angle)
        if self.reverse_b:
            path_b = reversed_path(path_b)
        ma, mb = object_mesh(obj_a), object_mesh(obj_b)
        same = obj_a == obj_b
        mode = "equal" if len(path_a) == len(path_b) else "unequal"
        name = unique_seam_name(scene, self.name or "Seam")
        seam = SeamData.from_tailor(tailor.Seam.from_paths(name, 0, ma, path_a, 0 if same else 1, mb, path_b, mode))
        objects = [obj_a] if same else [obj_a, obj_b]
        r = resolve(seam, [ma] if same else [ma, mb])
        add_seam_item(scene, seam, objects, r)
        self.report({"INFO"}, f"Seam '{name}': {len(path_a)} + {len(path_b)} vertices, {mode}")
        return {"FINISHED"}


class TAILOR_OT_seam_add(SeamAddProperties, bpy.types.Operator):
    bl_idname = "tailor.seam_add"
    bl_label = "Add Seam"
    bl_description = (
        "Sew two contour runs together: side A from a1 to an on one piece, side B from b1 on the same "
        "or another piece (contour positions)"
    )
    bl_options = {"REGISTER", "UNDO"}


class TAILOR_OT_seam_remove(bpy.types.Operator):
    bl_idname = "tailor.seam_remove"
    bl_label = "Delete Seam"
    bl_description = "Delete the active seam (the pieces are not changed)"
    bl_options = {"REGISTER", "UNDO"}

    index: IntProperty(name="Index", description="Seam to delete; -1: the active one", default=-1, min=-1)

    @classmethod
    def poll(cls, context):
        return len(context.scene.tailor.seams) > 0

    @reports_errors("Deleting the seam")
    def execute(self, context):
        settings = context.scene.tailor
        i, item = seam_at(context.scene, self.index)
        name = item.name
        settings.seams.remove(i)
        settings.seam_index = min(settings.seam_index, len(settings.seams) - 1)
        self.report({"INFO"}, f"Deleted seam '{name}'")
        return {"FINISHED"}


class TAILOR_OT_seam_flip(bpy.types.Operator):
    bl_idname = "tailor.seam_flip"
    bl_label = "Flip Seam"
    bl_description = "Reverse the direction of the active seam's side B (sew a1 to bn instead of b1)"
    bl_options = {"REGISTER", "UNDO"}

    index: IntProperty(name="Index", description="Seam to flip; -1: the active one", default=-1, min=-1)

    @classmethod
    def poll(cls, context):
        return len(context.scene.tailor.seams) > 0

    @reports_errors("Flipping the seam")
    def execute(self, context):
        _, item = seam_at(context.scene, self.index)
        objects, r = checked_seam(item, flip=True)
        seam = scene_data.read_seam(item, {o.name: i for i, o in enumerate(objects)}).flipped()
        scene_data.write_seam(item, seam, objects)
        store_seam_counts(item, r)
        return {"FINISHED"}


class TAILOR_OT_seam_rename(bpy.types.Operator):
    bl_idname = "tailor.seam_rename"
    bl_label = "Rename Seam"
    bl_description = "Rename the active seam"
    bl_options = {"REGISTER", "UNDO"}

    index: IntProperty(name="Index", description="Seam to rename; -1: the active one", default=-1, min=-1)
    new_name: StringProperty(name="Name")

    @classmethod
    def poll(cls, context):
        return len(context.scene.tailor.seams) > 0

    def invoke(self, context, event):
        self.new_name = seam_at(context.scene, self.index)[1].name
        return context.window_manager.invoke_props_dialog(self)

    @reports_errors("Renaming the seam")
    def execute(self, context):
        i, item = seam_at(context.scene, self.index)
        name = self.new_name.strip()
        if not name:
            raise AddonError("a seam name cannot be empty", "Type a name")
        if any(s.name == name for k, s in enumerate(context.scene.tailor.seams) if k != i):
            raise AddonError(f"another seam is already called '{name}'", "Choose another name")
        item.name = name
        return {"FINISHED"}


class TAILOR_OT_seams_update(bpy.types.Operator):
    bl_idname = "tailor.seams_update"
    bl_label = "Check Seams"
    bl_description = "Resolve every seam on the current piece meshes and refresh their vertex counts"
    bl_options = {"REGISTER", "UNDO"}

    @reports_errors("Checking the seams")
    def execute(self, context):
        results = [checked_seam(item) for item in context.scene.tailor.seams]
        for item, (_, r) in zip(context.scene.tailor.seams, results):
            store_seam_counts(item, r)
        self.report({"INFO"}, f"{len(results)} seams resolve on the current meshes")
        return {"FINISHED"}


def checked_seam(item, flip: bool = False) -> tuple[list, dict]:
    """(piece objects, resolution) of a stored seam (flipped first if asked); raises with the
    seam's name when a piece is gone or it no longer resolves."""
    if not (scene_data.is_piece(item.piece_a) and scene_data.is_piece(item.piece_b)):
        raise AddonError(f"seam '{item.name}' lost one of its pieces", "Delete the seam or re-create it")
    objects = [item.piece_a] if item.piece_a == item.piece_b else [item.piece_a, item.piece_b]
    seam = scene_data.read_seam(item, {o.name: i for i, o in enumerate(objects)})
    if flip:
        seam = seam.flipped()
    return objects, resolve(seam, [object_mesh(o) for o in objects])


classes = (
    TAILOR_OT_seam_add,
    TAILOR_OT_seam_add_segments,
    TAILOR_OT_seam_remove,
    TAILOR_OT_seam_flip,
    TAILOR_OT_seam_rename,
    TAILOR_OT_seams_update,
)
