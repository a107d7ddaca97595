"""Seams, stored at scene level (`Scene.tailor.seams`) and independent of the resolution.

Each side is the module's `SeamSide`: a piece object, the rest-frame (2D, metres) positions of
its first and last points, and the direction walked along the contour between them. Vertex
indices are never stored; resolving the sides on the current meshes finds them (and remaps
them after a re-triangulation). See docs/addon.md.
"""

import bpy
from bpy.props import (
    BoolProperty,
    CollectionProperty,
    EnumProperty,
    FloatProperty,
    FloatVectorProperty,
    IntProperty,
    PointerProperty,
)

DIRECTION_ITEMS = [
    ("CCW", "Counter-Clockwise", "Walk the contour counter-clockwise (the outline's own order)"),
    ("CW", "Clockwise", "Walk the contour clockwise"),
]
MODE_ITEMS = [
    ("EQUAL", "Equal", "One-to-one: both sides have the same number of vertices"),
    ("UNEQUAL", "Unequal", "Arc-length pairing: sides of different vertex counts (easing, gathering)"),
]


def _is_piece(self, obj) -> bool:
    return obj.type == "MESH" and obj.tailor_piece.is_piece


def _redraw(self, context) -> None:
    if context.screen is not None:
        for area in context.screen.areas:
            if area.type == "VIEW_3D":
                area.tag_redraw()


class TailorSeam(bpy.types.PropertyGroup):
    # `name` (the seam's name) comes with PropertyGroup.
    piece_a: PointerProperty(name="Piece A", type=bpy.types.Object, poll=_is_piece, description="First piece")
    a_start: FloatVectorProperty(name="A Start", size=2, subtype="XYZ", description="Rest position of a1, metres")
    a_end: FloatVectorProperty(name="A End", size=2, subtype="XYZ", description="Rest position of an, metres")
    a_direction: EnumProperty(name="A Direction", items=DIRECTION_ITEMS, default="CCW")
    piece_b: PointerProperty(name="Piece B", type=bpy.types.Object, poll=_is_piece, description="Second piece")
    b_start: FloatVectorProperty(name="B Start", size=2, subtype="XYZ", description="Rest position of b1, metres")
    b_end: FloatVectorProperty(name="B End", size=2, subtype="XYZ", description="Rest position of bn, metres")
    b_direction: EnumProperty(name="B Direction", items=DIRECTION_ITEMS, default="CCW")
    mode: EnumProperty(name="Mode", items=MODE_ITEMS, default="EQUAL", description="How the two sides are paired")
    stiffness: FloatProperty(
        name="Stiffness",
        description="Factor on the solver's seam stiffness (distance springs between the sides)",
        default=1.0,
        min=0.0,
        soft_max=10.0,
    )
    bend_stiffness: FloatProperty(
        name="Bending Stiffness",
        description="Factor on the solver's bending stiffness across the seam",
        default=1.0,
        min=0.0,
        soft_max=10.0,
    )
    show: BoolProperty(name="Show", description="Draw this seam in the viewport", default=True, update=_redraw)
    color: FloatVectorProperty(
        name="Colour", subtype="COLOR", size=3, min=0.0, max=1.0, default=(1.0, 0.4, 0.1), update=_redraw
    )
    # Vertex counts of the sides on the current meshes (updated whenever the seam is resolved).
    a_count: IntProperty(name="A Vertices", min=0)
    b_count: IntProperty(name="B Vertices", min=0)


class TailorSceneSettings(bpy.types.PropertyGroup):
    seams: CollectionProperty(type=TailorSeam)
    seam_index: IntProperty(name="Active Seam", default=0)
    show_seams: BoolProperty(name="Show Seams", description="Draw seams in the viewport", default=True, update=_redraw)
    show_collision_levels: BoolProperty(
        name="Show Collision Levels",
        description="Draw every vertex with collision levels as a dot coloured by its level",
        default=True,
        update=_redraw,
    )
    corner_angle: FloatProperty(
        name="Corner Angle",
        description="Contour angles under this are corners (automatic seam suggestion)",
        subtype="ANGLE",
        default=2.6179938779914944,  # 150 degrees
        min=0.0,
        max=3.141592653589793,
    )


classes = (TailorSeam, TailorSceneSettings)


def register() -> None:
    bpy.types.Scene.tailor = PointerProperty(type=TailorSceneSettings)


def unregister() -> None:
    del bpy.types.Scene.tailor
