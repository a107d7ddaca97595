"""Import a sewing pattern as piece objects; re-triangulate pieces at a new resolution."""

import os

import bpy
from bpy.props import BoolProperty, EnumProperty, FloatProperty, StringProperty
from bpy_extras.io_utils import ExportHelper, ImportHelper
from mathutils import Euler, Matrix

import tailor

from .. import scene_data
from ..core import AddonError, mesh_arrays, placement_rotation, side_by_side
from ..core.garment import SeamData
from ..core.layout import PLACEMENT_ROTATION_MODE, Y_UP_TO_Z_UP
from ..reporting import reports_errors
from ..seams.store import add_seam_item
from . import rebuild

UNITS = [
    ("AUTO", "From File", "Use the units the file declares (DXF header, SVG width/viewBox, GarmentCode cm)"),
    ("mm", "Millimetres", ""),
    ("cm", "Centimetres", ""),
    ("m", "Metres", ""),
    ("inch", "Inches", ""),
    ("ft", "Feet", ""),
    ("px", "Pixels (1/96 inch)", ""),
    ("pt", "Points (1/72 inch)", ""),
]


def select_only(context, objects: list) -> None:
    """Selects exactly `objects` (what an import made), the first one active."""
    for o in context.view_layer.objects:
        o.select_set(False)
    for o in objects:
        o.select_set(True)
    if objects:
        context.view_layer.objects.active = objects[0]


class TAILOR_OT_import_pattern(bpy.types.Operator, ImportHelper):
    bl_idname = "tailor.import_pattern"
    bl_label = "Import Sewing Pattern"
    bl_description = (
        "Import a sewing pattern (DXF, SVG or GarmentCode JSON): one mesh object per piece, "
        "GarmentCode placements and stitches applied"
    )
    bl_options = {"REGISTER", "UNDO"}

    filter_glob: StringProperty(default="*.dxf;*.DXF;*.svg;*.SVG;*.json;*.JSON", options={"HIDDEN"})
    edge_length: FloatProperty(
        name="Resolution",
        description="Target triangle edge length of the piece meshes",
        subtype="DISTANCE",
        unit="LENGTH",
        default=0.02,
        min=0.002,
        soft_max=0.1,
        precision=4,
    )
    size: StringProperty(name="Size", description="Size to import from a graded DXF (empty: the base size)")
    units: EnumProperty(name="Units", description="Units of the file's coordinates", items=UNITS, default="AUTO")
    use_placement: BoolProperty(
        name="Placements", description="Place pieces around the body where the file says (GarmentCode)", default=True
    )
    up_axis: EnumProperty(
        name="Placement Up",
        description="Up axis of the file's placements",
        items=[
            (
                "Y",
                "Y Up",
                "Y is up in the file (GarmentCode and its bodies): turn it to Blender's Z up, as the OBJ "
                "importer does",
            ),
            ("Z", "Z Up", "Use the placements as they are"),
        ],
        default="Y",
    )
    use_stitches: BoolProperty(
        name="Stitches as Seams", description="Turn the file's stitches into seams (GarmentCode)", default=True
    )
    use_unfold: BoolProperty(
        name="Unfold Halves",
        description="A DXF piece drawn as a half with a mirror line along its fold (cut on the fold) becomes the "
                    "whole piece; off, it stays as drawn",
        default=True,
    )
    use_quantities: BoolProperty(
        name="Cut Quantities",
        description="Import a DXF piece as many times as the file says to cut it: a pair as the piece and its "
                    "mirror image (named R and L), a piece cut 0 times left out; off, every piece once as drawn",
        default=True,
    )

    @reports_errors("Importing the pattern")
    def execute(self, context):
        path = bpy.path.abspath(self.filepath)
        if not os.path.isfile(path):
            raise AddonError(f"no pattern file at '{path}'", "Choose an existing .dxf, .svg or .json file")
        # Everything is computed before the scene is touched: an error leaves it unchanged.
        g = tailor.Garment.from_pattern(
            path, edge=self.edge_length, size=self.size or None, units=None if self.units == "AUTO" else self.units,
            unfold=self.use_unfold, quantities=self.use_quantities,
        )
        pieces, meshes = g.pieces, g.meshes()
        arrays = [mesh_arrays(m) for m in meshes]
        seams = [SeamData.from_tailor(s) for s in g.seams] if self.use_stitches else []
        resolved = [s.to_tailor().resolve(meshes) for s in seams]
        flat = [i for i, p in enumerate(pieces) if not (self.use_placement and p.placement)]
        locations = dict(zip(flat, side_by_side([meshes[i].rest for i in flat])))

        scene = context.scene
        stem = os.path.splitext(os.path.basename(path))[0]
        coll = bpy.data.collections.new(stem)
        scene.collection.children.link(coll)
        objects = []
        for i, (piece, mesh, arr) in enumerate(zip(pieces, meshes, arrays)):
            obj = scene_data.new_piece_object(
                coll, piece.name, arr, piece_json=piece.to_json(), source_path=path, source_index=i,
                edge_length=self.edge_length, mesher=tailor.MESHER_VERSION, contour_length=mesh.contour_length)
            if i in locations:
                obj.location = locations[i]
            else:
                obj.rotation_mode = PLACEMENT_ROTATION_MODE
                obj.matrix_world = self.placement_matrix(piece.placement)
            objects.append(obj)
        for seam, r in zip(seams, resolved):
            add_seam_item(scene, seam, objects, r)

        select_only(context, objects)
        for w in g.warnings:
            self.report({"WARNING"}, w)
        self.report({"INFO"}, f"Imported {len(objects)} pieces and {len(seams)} seams from {os.path.basename(path)}")
        return {"FINISHED"}

    def placement_matrix(self, placement: dict) -> Matrix:
        loc, rot = placement_rotation(placement)
        m = Matrix.Translation(loc) @ Euler(rot, PLACEMENT_ROTATION_MODE).to_matrix().to_4x4()
        if self.up_axis == "Y":
            m = Matrix(Y_UP_TO_Z_UP.tolist()).to_4x4() @ m
        return m


class TAILOR_OT_set_resolution(bpy.types.Operator):
    bl_idname = "tailor.set_resolution"
    bl_label = "Set Piece Resolution"
    bl_description = (
        "Re-triangulate the selected garment pieces at a new edge length, in place; "
        "their seams are remapped and painted values carried over"
    )
    bl_options = {"REGISTER", "UNDO"}

    edge_length: FloatProperty(
        name="Resolution",
        description="Target triangle edge length",
        subtype="DISTANCE",
        unit="LENGTH",
        default=0.02,
        min=0.002,
        soft_max=0.1,
        precision=4,
    )

    @classmethod
    def poll(cls, context):
        return any(scene_data.is_piece(o) for o in context.selected_objects) or scene_data.is_piece(
            context.active_object
        )

    def invoke(self, context, event):
        if scene_data.is_piece(context.active_object):
            self.edge_length = context.active_object.tailor_piece.edge_length
        return context.window_manager.invoke_props_dialog(self)

    @reports_errors("Changing the resolution")
    def execute(self, context):
        targets = [o for o in context.selected_objects if scene_data.is_piece(o)]
        if not targets and scene_data.is_piece(context.active_object):
            targets = [context.active_object]
        if not targets:
            raise AddonError("no garment piece is selected", "Select the pieces to re-triangulate")
        if any(o.mode != "OBJECT" for o in targets):
            raise AddonError("a piece to re-triangulate is in Edit Mode", "Switch to Object Mode first")
        rebuild.set_resolution(context.scene, targets, self.edge_length)
        self.report({"INFO"}, f"Re-triangulated {len(targets)} piece(s) at {self.edge_length * 100:.3g} cm")
        return {"FINISHED"}


def exported_garment(scene, garment: str | None, name: str):
    """The scene's garment as a `tailor.Garment` to save: pieces as they stand (and their
    placements and bends), seams, and the setup and painted maps the panels give it, exactly
    what the add-on simulates (`core.simulate.garment_of`)."""
    from ..core import simulate as core_sim
    from ..paint.maps import collision_levels, painted_maps
    from ..simulate import gather

    objects = scene_data.piece_objects(scene, garment)
    colliders = gather.collider_objects(scene)
    levels = collision_levels(colliders[0]) if colliders else None
    g = scene_data.garment_file(scene, garment)
    return core_sim.garment_of(g, name, gather.sim_settings(scene), gather.fabrics(objects),
                               [painted_maps(o) for o in objects], levels)


class TAILOR_OT_export_garment(bpy.types.Operator, ExportHelper):
    bl_idname = "tailor.export_garment"
    bl_label = "Export Tailor Garment"
    bl_description = (
        "Write the scene's garment (pieces, resolutions, placements, bends, seams, fabric, painted pins and "
        "collision levels, thickness and self-collision) as a Tailor garment file (.json + .bin) that the tailor "
        "module simulates without Blender"
    )
    # A file exporter changes no data: no undo step (as Blender's own exporters).
    bl_options = {"REGISTER"}

    filename_ext = ".json"
    filter_glob: StringProperty(default="*.json", options={"HIDDEN"})
    garment: StringProperty(name="Garment", description="Only this garment's pieces (empty: every piece)")

    @reports_errors("Exporting the garment")
    def execute(self, context):
        path = bpy.path.abspath(self.filepath)
        g = exported_garment(context.scene, self.garment or None, os.path.splitext(os.path.basename(path))[0])
        g.save(path)
        painted = sum(1 for name, _, _ in g.particle_params if name != "position")
        self.report({"INFO"}, f"Wrote {os.path.basename(path)}: {len(g.pieces)} pieces, {len(g.seams)} seams, "
                              f"{painted} painted maps")
        return {"FINISHED"}


classes = (TAILOR_OT_import_pattern, TAILOR_OT_set_resolution, TAILOR_OT_export_garment)
