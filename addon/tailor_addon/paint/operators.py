"""Paint operators: set a map on the edit-mode selection, start weight painting a map, clear.

Weight maps are ordinary vertex groups, so Blender's own weight paint edits them; these
operators add the exact-value path (select vertices in edit mode, set a value) and the integer
collision levels, which weight paint cannot hold as one map: they are set on a selection (the
level attribute) or painted a level at a time, each level its own vertex group painted with the
weight brush (`core.paint.painted_levels`). All work on the active mesh object: a garment piece,
or the character (collision levels).
"""

import bpy
import numpy as np
from bpy.props import BoolProperty, EnumProperty, FloatProperty, IntProperty

from ..core import AddonError
from ..core.paint import BY_KEY, LEVEL_ATTR, WEIGHT_MAPS, level_group_name, level_of_group
from ..reporting import reports_errors

MAP_ITEMS = [(m.key.upper(), m.label, m.meaning) for m in WEIGHT_MAPS]
CLEAR_ITEMS = MAP_ITEMS + [("COLLISION_LEVEL", "Collision Level",
                            "The integer collision levels: the attribute and every painted level group")]


def active_mesh(context):
    obj = context.active_object
    if obj is None or obj.type != "MESH":
        raise AddonError("no active mesh object", "Select a garment piece or the character")
    return obj


def selected_vertices(obj, only_selected: bool) -> np.ndarray:
    """Indices of the vertices to set: the edit-mode selection (synced to the mesh) or all."""
    if obj.mode == "EDIT":
        obj.update_from_editmode()
    n = len(obj.data.vertices)
    if not only_selected:
        return np.arange(n)
    sel = np.zeros(n, bool)
    obj.data.vertices.foreach_get("select", sel)
    idx = np.nonzero(sel)[0]
    if len(idx) == 0:
        raise AddonError(f"no vertex of '{obj.name}' is selected", "Select vertices in Edit Mode first")
    return idx


class _ObjectMode:
    """Vertex groups and attributes are written in Object Mode; come back to where we were."""

    def __init__(self, obj):
        self.obj, self.mode = obj, obj.mode

    def __enter__(self):
        if self.mode != "OBJECT":
            bpy.ops.object.mode_set(mode="OBJECT")

    def __exit__(self, *exc):
        if self.mode != "OBJECT":
            bpy.ops.object.mode_set(mode=self.mode)
        return False


class TAILOR_OT_paint_set(bpy.types.Operator):
    bl_idname = "tailor.paint_set"
    bl_label = "Set Painted Value"
    bl_description = (
        "Set friction, mass scale or pin weight (a vertex-group weight, 0 to 1) on the selected vertices "
        "of the active mesh (all vertices outside Edit Mode)"
    )
    bl_options = {"REGISTER", "UNDO"}

    map: EnumProperty(name="Map", items=MAP_ITEMS)
    value: FloatProperty(name="Weight", description="Vertex-group weight to set", default=1.0, min=0.0, max=1.0)
    only_selected: BoolProperty(name="Only Selected", description="Only the selected vertices", default=True)

    @classmethod
    def poll(cls, context):
        return context.active_object is not None and context.active_object.type == "MESH"

    @reports_errors("Setting the painted value")
    def execute(self, context):
        obj = active_mesh(context)
        idx = selected_vertices(obj, self.only_selected and obj.mode == "EDIT")
        group = BY_KEY[self.map.lower()].group
        with _ObjectMode(obj):
            vg = obj.vertex_groups.get(group) or obj.vertex_groups.new(name=group)
            vg.add(idx.tolist(), float(self.value), "REPLACE")
        self.report({"INFO"}, f"{BY_KEY[self.map.lower()].label} = {self.value:.3g} on {len(idx)} vertices")
        return {"FINISHED"}


class TAILOR_OT_paint_weights(bpy.types.Operator):
    bl_idname = "tailor.paint_weights"
    bl_label = "Weight Paint Map"
    bl_description = (
        "Weight paint a Tailor map on the active mesh with Blender's own brushes (creates its vertex group)"
    )
    bl_options = {"REGISTER", "UNDO"}

    map: EnumProperty(name="Map", items=MAP_ITEMS)

    @classmethod
    def poll(cls, context):
        return context.active_object is not None and context.active_object.type == "MESH"

    @reports_errors("Starting weight paint")
    def execute(self, context):
        obj = active_mesh(context)
        group = BY_KEY[self.map.lower()].group
        vg = obj.vertex_groups.get(group) or obj.vertex_groups.new(name=group)
        obj.vertex_groups.active_index = vg.index
        if obj.mode != "WEIGHT_PAINT":
            bpy.ops.object.mode_set(mode="WEIGHT_PAINT")
        return {"FINISHED"}


class TAILOR_OT_collision_level_set(bpy.types.Operator):
    bl_idname = "tailor.collision_level_set"
    bl_label = "Set Collision Level"
    bl_description = (
        "Set the collision level of the selected vertices of the active mesh (a garment piece or the character); "
        "all vertices outside Edit Mode"
    )
    bl_options = {"REGISTER", "UNDO"}

    level: IntProperty(name="Level", description="Collision level (layers collide by level)", default=1, min=0)
    only_selected: BoolProperty(name="Only Selected", description="Only the selected vertices", default=True)

    @classmethod
    def poll(cls, context):
        return context.active_object is not None and context.active_object.type == "MESH"

    @reports_errors("Setting the collision level")
    def execute(self, context):
        obj = active_mesh(context)
        idx = selected_vertices(obj, self.only_selected and obj.mode == "EDIT")
        with _ObjectMode(obj):
            me = obj.data
            attr = me.attributes.get(LEVEL_ATTR)
            if attr is not None and (attr.domain != "POINT" or attr.data_type != "INT"):
                raise AddonError(
                    f"'{obj.name}' has an attribute '{LEVEL_ATTR}' that is not an integer per vertex",
                    "Clear the collision levels first",
                )
            levels = np.zeros(len(me.vertices), np.int32)
            if attr is None:
                attr = me.attributes.new(LEVEL_ATTR, "INT", "POINT")
            else:
                attr.data.foreach_get("value", levels)
            levels[idx] = self.level
            attr.data.foreach_set("value", levels)
            me.update()
        self.report({"INFO"}, f"Collision level {self.level} on {len(idx)} vertices")
        return {"FINISHED"}


class TAILOR_OT_collision_level_paint(bpy.types.Operator):
    bl_idname = "tailor.collision_level_paint"
    bl_label = "Paint Collision Level"
    bl_description = (
        "Paint a collision level with the weight brush: its own vertex group (tailor_level_N) on the active mesh; "
        "where its weight is 0.5 or more the vertex takes this level (the heaviest level group wins), elsewhere the "
        "level set on a selection"
    )
    bl_options = {"REGISTER", "UNDO"}

    level: IntProperty(name="Level", description="Collision level to paint (layers collide by level)", default=1,
                       min=0, max=65536)

    @classmethod
    def poll(cls, context):
        return context.active_object is not None and context.active_object.type == "MESH"

    def invoke(self, context, event):
        return context.window_manager.invoke_props_dialog(self)

    @reports_errors("Starting to paint a collision level")
    def execute(self, context):
        obj = active_mesh(context)
        name = level_group_name(self.level)
        vg = obj.vertex_groups.get(name) or obj.vertex_groups.new(name=name)
        obj.vertex_groups.active_index = vg.index
        context.scene.tailor.show_collision_levels = True
        if obj.mode != "WEIGHT_PAINT":
            bpy.ops.object.mode_set(mode="WEIGHT_PAINT")
        return {"FINISHED"}


class TAILOR_OT_paint_clear(bpy.types.Operator):
    bl_idname = "tailor.paint_clear"
    bl_label = "Clear Painted Map"
    bl_description = "Remove a painted map (vertex group or collision levels) from the active mesh"
    bl_options = {"REGISTER", "UNDO"}

    map: EnumProperty(name="Map", items=CLEAR_ITEMS)

    @classmethod
    def poll(cls, context):
        return context.active_object is not None and context.active_object.type == "MESH"

    @reports_errors("Clearing the painted map")
    def execute(self, context):
        obj = active_mesh(context)
        with _ObjectMode(obj):
            if self.map == "COLLISION_LEVEL":
                attr = obj.data.attributes.get(LEVEL_ATTR)
                groups = [vg for vg in obj.vertex_groups if level_of_group(vg.name) is not None]
                if attr is None and not groups:
                    raise AddonError(f"'{obj.name}' has no collision levels", "Nothing to clear")
                if attr is not None:
                    obj.data.attributes.remove(attr)
                for vg in groups:
                    obj.vertex_groups.remove(vg)
            else:
                vg = obj.vertex_groups.get(BY_KEY[self.map.lower()].group)
                if vg is None:
                    raise AddonError(f"'{obj.name}' has no {BY_KEY[self.map.lower()].label} map", "Nothing to clear")
                obj.vertex_groups.remove(vg)
        return {"FINISHED"}


classes = (
    TAILOR_OT_paint_set,
    TAILOR_OT_paint_weights,
    TAILOR_OT_collision_level_set,
    TAILOR_OT_collision_level_paint,
    TAILOR_OT_paint_clear,
)
