"""Arrange on Body: the selected pieces (or the whole garment) put round the collider body."""

from __future__ import annotations

import bpy
import numpy as np
from bpy.props import FloatProperty

from .. import scene_data
from ..core import AddonError
from ..core import arrange as core_arrange
from ..reporting import reports_errors
from ..simulate import gather

#: The last places found: {"collider": name, "places": [...]} (the viewport draws them).
last_places: dict = {}


def collider_of(scene):
    """The scene's collider (the first object marked as one), or an AddonError."""
    colliders = gather.collider_objects(scene)
    if not colliders:
        raise AddonError(
            "the scene has no collider", "Select the body and use Mark Collider (Simulate panel) first"
        )
    return colliders[0]


def places_of(scene, collider=None) -> list[dict]:
    """The body places of the scene's collider (evaluated mesh, world space, Z up)."""
    body = collider if collider is not None else collider_of(scene)
    dg = bpy.context.evaluated_depsgraph_get()
    v = gather.evaluated_positions(body, dg)
    t = gather.evaluated_triangles(body, dg)
    places = core_arrange.find_places(v, t, body=body.name, up="z")
    last_places.clear()
    last_places.update(collider=body.name, places=places)
    return places


def target_pieces(context) -> list:
    """The selected pieces, else every piece of the active piece's garment (of the scene when
    the active object is no piece)."""
    selected = [o for o in context.selected_objects if scene_data.is_piece(o)]
    if selected:
        return sorted(selected, key=lambda o: o.name)
    active = context.active_object
    garment = active.tailor_piece.garment if scene_data.is_piece(active) else None
    return scene_data.piece_objects(context.scene, garment)


class TAILOR_OT_arrange_on_body(bpy.types.Operator):
    bl_idname = "tailor.arrange_on_body"
    bl_label = "Arrange on Body"
    bl_description = (
        "Put the selected pieces (none selected: the whole garment) round the collider body, each on its "
        "place (the piece's Place, or Auto: by its name and shape), rolled round the body without stretching"
    )
    bl_options = {"REGISTER", "UNDO"}

    clearance: FloatProperty(
        name="Clearance",
        description="How far off the body every point of the pieces is put",
        subtype="DISTANCE",
        unit="LENGTH",
        default=core_arrange.CLEARANCE,
        min=0.0,
        soft_max=0.2,
    )

    @classmethod
    def poll(cls, context):
        return context.scene is not None and any(scene_data.is_piece(o) for o in context.scene.objects)

    @reports_errors("Arranging on the body")
    def execute(self, context):
        pieces = target_pieces(context)
        if not pieces:
            raise AddonError("no garment pieces to arrange", "Import a sewing pattern first")
        for o in pieces:
            if o.mode != "OBJECT":
                raise AddonError(f"piece '{o.name}' is in edit mode", "Switch to Object Mode to arrange it")
        rests = []
        for o in pieces:
            rest = scene_data.rest_of(o)
            if rest is None or len(rest) != len(o.data.vertices):
                raise AddonError(
                    f"piece '{o.name}' has no rest shape matching its mesh",
                    "Set its resolution again (Patterns panel) to rebuild it",
                )
            rests.append(rest)
        places = places_of(context.scene)
        names = [o.tailor_piece.piece_name or o.name for o in pieces]
        grains = [core_arrange.grain_of(o.tailor_piece.piece_json) for o in pieces]
        result = core_arrange.arrange(
            names, rests, places, [o.tailor_piece.place for o in pieces], clearance=self.clearance, grains=grains
        )
        # Everything computed: now the scene changes.
        for o, r in zip(pieces, result):
            co = core_arrange.to_local(r.positions, np.array(o.matrix_world))
            o.data.vertices.foreach_set("co", np.ascontiguousarray(co, np.float32).reshape(-1))
            o.data.update()
            p = o.tailor_piece
            p.arranged_place = r.entry["place"]
            # The mesh is no longer the stored bend of the flat piece: forget it (a change of
            # resolution then rebuilds the piece flat, to be arranged again).
            p.bend_angle = 0.0
        counts: dict[str, int] = {}
        for r in result:
            counts[r.entry["place"]] = counts.get(r.entry["place"], 0) + 1
        where = ", ".join(f"{n} on {p}" for p, n in counts.items())
        self.report({"INFO"}, f"Arranged {len(result)} pieces on '{last_places['collider']}': {where}")
        return {"FINISHED"}


classes = (TAILOR_OT_arrange_on_body,)
