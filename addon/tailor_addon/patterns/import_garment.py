"""File > Import > Tailor Garment: a garment file (as File > Export > Tailor Garment writes it)
back into the scene: one piece object per piece, placed and bent, with its fabric and painted
maps; the seams; the Simulate panel's settings; the collider's painted levels when the scene's
collider is the mesh they were painted on.

Everything is read and checked first (`core.garment_import.read_garment_file`, and the
collider's levels here); only then is the scene changed, so a bad file is a report and leaves
the scene as it was.
"""

import os

import bpy
from bpy.props import EnumProperty, StringProperty
from bpy_extras.io_utils import ImportHelper

from .. import scene_data
from ..core import AddonError, fabric_presets
from ..core.garment_import import ImportedGarment, ImportedPiece, read_garment_file
from ..core.layout import PLACEMENT_ROTATION_MODE
from ..paint.maps import write_collision_levels, write_group
from ..reporting import reports_errors
from ..seams.store import add_seam_item
from .operators import select_only


def collider_levels(scene, imported: ImportedGarment):
    """(collider object, its levels) to write, or (None, None); and the warning when the
    file's levels could not be applied. The collider is the one the export reads them from:
    the scene's first (`simulate.gather.collider_objects`)."""
    from ..simulate import gather

    if imported.collider_vertices is None:
        return None, None, None
    colliders = gather.collider_objects(scene)
    collider = colliders[0] if colliders else None
    if collider is not None and collider.mode != "OBJECT":
        return None, None, f"the file's collider collision levels were not applied: '{collider.name}' is in Edit Mode"
    levels, warning = imported.collider_levels(collider.name if collider else None,
                                               len(collider.data.vertices) if collider else 0)
    return (collider if levels is not None else None), levels, warning


def write_piece(coll, piece: ImportedPiece, path: str, index: int):
    """The piece's object, as Import Sewing Pattern makes it, with the file's transform, bend,
    fabric and painted maps."""
    obj = scene_data.new_piece_object(
        coll, piece.name, piece.arrays, piece_json=piece.piece_json, source_path=path, source_index=index,
        edge_length=piece.edge_length, mesher=piece.mesher, contour_length=piece.contour_length)
    obj.rotation_mode = PLACEMENT_ROTATION_MODE
    obj.location, obj.rotation_euler = piece.location, piece.rotation
    p = obj.tailor_piece
    fabric_presets.set_piece_fabric(p, fabric_presets.fabric_values(piece.fabric))
    b = piece.bend
    if b is not None:
        p.bend_angle = b.angle
        p.bend_axis_point, p.bend_axis_direction = b.axis_point, b.axis_direction
        p.bend_symmetry = b.symmetry is not None
        if b.symmetry is not None:
            p.bend_symmetry_point, p.bend_symmetry_direction = b.symmetry
        p.bend_threshold, p.bend_rolled = b.threshold, b.rolled
        p.bend_radius, p.bend_taper = b.radius or 0.0, b.taper
    for group, (indices, weights) in piece.groups.items():
        write_group(obj, group, indices, weights)
    if piece.levels is not None:
        write_collision_levels(obj, piece.levels)
    return obj


class TAILOR_OT_import_garment(bpy.types.Operator, ImportHelper):
    bl_idname = "tailor.import_garment"
    bl_label = "Import Tailor Garment"
    bl_description = (
        "Import a Tailor garment file (.json + .bin, as Export Tailor Garment writes it): its pieces placed and "
        "bent, seams, fabric, painted maps and simulation settings"
    )
    bl_options = {"REGISTER", "UNDO"}

    filename_ext = ".json"
    filter_glob: StringProperty(default="*.json;*.JSON", options={"HIDDEN"})
    up_axis: EnumProperty(
        name="Placement Up",
        description="Up axis of the file's placements",
        items=[
            ("AUTO", "From File", "The up axis the file states (Z for files the add-on wrote); a file that states "
             "none is taken as Y up, as GarmentCode's"),
            ("Y", "Y Up", "Y is up in the file: turn the placed pieces to Blender's Z up, as the OBJ importer does"),
            ("Z", "Z Up", "Use the placements as they are"),
        ],
        default="AUTO",
    )

    @reports_errors("Importing the garment")
    def execute(self, context):
        path = bpy.path.abspath(self.filepath)
        if not os.path.isfile(path):
            raise AddonError(f"no garment file at '{path}'", "Choose the .json of a Tailor garment file")
        # Everything is computed before the scene is touched: an error leaves it unchanged.
        imported = read_garment_file(path, self.up_axis)
        scene = context.scene
        collider, levels, levels_warning = collider_levels(scene, imported)

        coll = bpy.data.collections.new(os.path.splitext(os.path.basename(path))[0])
        scene.collection.children.link(coll)
        objects = [write_piece(coll, piece, path, i) for i, piece in enumerate(imported.pieces)]
        for seam, r in zip(imported.seams, imported.resolved):
            add_seam_item(scene, seam, objects, r)
        settings = scene.tailor_simulate
        for name, value in imported.settings.items():
            setattr(settings, name, value)
        if collider is not None:
            write_collision_levels(collider, levels)

        select_only(context, objects)
        for w in imported.warnings + ([levels_warning] if levels_warning else []):
            self.report({"WARNING"}, w)
        applied = f", the collider levels of '{collider.name}'" if collider is not None else ""
        self.report({"INFO"}, f"Imported {len(objects)} pieces, {len(imported.seams)} seams, "
                              f"{imported.painted_maps} painted maps{applied} and the simulation settings from "
                              f"{os.path.basename(path)}")
        return {"FINISHED"}


classes = (TAILOR_OT_import_garment,)
