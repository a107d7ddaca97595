"""Per-piece data kept on the piece object (`Object.tailor_piece`); see docs/addon.md."""

import bpy
from bpy.props import BoolProperty, EnumProperty, FloatProperty, FloatVectorProperty, IntProperty, StringProperty

import tailor

from ..core import fabric_presets
from ..core.arrange import AUTO, place_items

_DEFAULT = tailor.Fabric()
_FABRIC_ITEMS = fabric_presets.items()  # kept: Blender needs the enum's strings to stay alive


_APPLYING: set = set()  # pieces whose fabric is being set from the library (not edits by hand)


def _apply_fabric(self, _context) -> None:
    """A library fabric chosen: its four values (Custom keeps the piece's own)."""
    if self.fabric == fabric_presets.CUSTOM:
        return
    key = self.as_pointer()
    _APPLYING.add(key)
    try:
        fabric_presets.set_piece_fabric(self, fabric_presets.values(self.fabric))
    finally:
        _APPLYING.discard(key)


def _edited_fabric(self, _context) -> None:
    """A value typed by hand: the piece is Custom unless the values are still its fabric's."""
    if self.as_pointer() in _APPLYING:
        return
    current = fabric_presets.piece_values(self)
    if self.fabric != fabric_presets.CUSTOM and not fabric_presets.matches(self.fabric, current):
        self.fabric = fabric_presets.CUSTOM


class TailorPieceSettings(bpy.types.PropertyGroup):
    is_piece: BoolProperty(name="Garment Piece", description="This mesh is a Tailor garment piece", default=False)
    piece_name: StringProperty(name="Piece", description="Name of the piece in its pattern file")
    garment: StringProperty(name="Garment", description="The garment this piece belongs to (its pattern's name)")
    source_path: StringProperty(
        name="Pattern File", description="The file the piece was imported from", subtype="FILE_PATH"
    )
    source_index: IntProperty(name="Index in File", description="Position of the piece in its pattern file", min=0)
    piece_json: StringProperty(
        name="Pattern Piece",
        description="The pattern piece itself (outline, holes, lines, notches) as the module stores it; "
        "the mesh is rebuilt from it",
        options={"HIDDEN"},
    )
    edge_length: FloatProperty(
        name="Resolution",
        description="Target edge length the piece is triangulated at",
        subtype="DISTANCE",
        unit="LENGTH",
        min=0.001,
        default=0.02,
        precision=4,
    )
    # Which mesher made the mesh (`tailor.MESHER_VERSION` when imported or re-triangulated); the
    # default 1 is what a piece saved before the field existed was made with, so it is rebuilt
    # vertex for vertex as it was saved.
    mesher: IntProperty(
        name="Mesher", description="Version of the mesher that made this piece's mesh", min=1, default=1,
        options={"HIDDEN"},
    )
    contour_length: FloatProperty(name="Contour Length", subtype="DISTANCE", unit="LENGTH")
    # Fabric of this piece (the Simulate panel builds per-piece stiffness and mass from these),
    # chosen from the library (`core.fabric_presets`) or typed.
    fabric: EnumProperty(
        name="Fabric", description="A measured fabric from the library, or Custom values",
        items=_FABRIC_ITEMS, default=fabric_presets.CUSTOM, update=_apply_fabric,
    )
    density: FloatProperty(
        name="Density", description="Mass per area, kg/m²", min=1e-4, default=_DEFAULT.density, precision=3,
        update=_edited_fabric,
    )
    stretch: FloatProperty(
        name="Stretch", description="Stretch stiffness of the fabric, N/m", min=0.0, default=_DEFAULT.stretch,
        update=_edited_fabric,
    )
    shear: FloatProperty(
        name="Shear", description="Shear stiffness of the fabric, N/m", min=0.0, default=_DEFAULT.shear,
        update=_edited_fabric,
    )
    bend: FloatProperty(
        name="Bend",
        description="Bending stiffness of the fabric's hinge model, N·m: a fabric of flexural rigidity B has B/3 "
                    "(the library's fabrics are converted so)",
        min=0.0, default=_DEFAULT.bend, precision=7, update=_edited_fabric,
    )
    # An anisotropic fabric (`tailor.Fabric`): u is the pattern's x axis, v its y axis; off, the
    # three values below are not used (the fabric is the same in every direction).
    anisotropic: BoolProperty(
        name="Anisotropic",
        description="The fabric differs by direction: stretch along the pattern's y axis (v) and bending by a "
                    "fold's direction (the library's measured fabrics are)",
        default=False, update=_edited_fabric,
    )
    stretch_v: FloatProperty(
        name="Stretch V", description="Stretch stiffness along the pattern's y axis (v), N/m; Stretch is along x (u)",
        min=0.0, default=_DEFAULT.stretch, update=_edited_fabric,
    )
    bend_bias: FloatProperty(
        name="Bend Bias", description="Bending stiffness of folds on the bias (45 degrees), N·m",
        min=0.0, default=_DEFAULT.bend, precision=7, update=_edited_fabric,
    )
    bend_v: FloatProperty(
        name="Bend V", description="Bending stiffness of folds whose edge runs along v, N·m; Bend is along u",
        min=0.0, default=_DEFAULT.bend, precision=7, update=_edited_fabric,
    )
    # The last bend applied (re-applied after a change of resolution; angle 0 = flat).
    bend_angle: FloatProperty(name="Bend Angle", subtype="ANGLE", default=0.0)
    bend_axis_point: FloatVectorProperty(name="Bend Axis Point", size=3, subtype="TRANSLATION")
    bend_axis_direction: FloatVectorProperty(name="Bend Axis Direction", size=3, default=(0.0, 1.0, 0.0))
    bend_symmetry: BoolProperty(name="Bend Symmetry", default=False)
    bend_symmetry_point: FloatVectorProperty(name="Symmetry Point", size=2)
    bend_symmetry_direction: FloatVectorProperty(name="Symmetry Direction", size=2, default=(0.0, 1.0))
    bend_threshold: FloatProperty(name="Bend Threshold", subtype="DISTANCE", unit="LENGTH", min=0.0)
    # How: rolled onto a cylinder, lengths kept (the Bend operator's); off in files bent before,
    # whose pieces were rotated as in the paper and are re-bent so (`tailor.bend`'s `mode`).
    bend_rolled: BoolProperty(name="Bend Rolled", default=False)
    # The roll's cylinder radius (0: from the angle) and cone half-angle (0: a cylinder).
    bend_radius: FloatProperty(name="Bend Radius", subtype="DISTANCE", unit="LENGTH", min=0.0, default=0.0)
    bend_taper: FloatProperty(name="Bend Taper", subtype="ANGLE", default=0.0)
    # Where Arrange on Body puts the piece (`core.arrange`): AUTO, the place its name and shape
    # suggest, or one of the body's places (`tailor.PLACE_NAMES`) the artist chose.
    place: EnumProperty(
        name="Place",
        description="Where Arrange on Body puts this piece on the collider body",
        items=place_items(),
        default=AUTO,
    )
    # The place the last Arrange on Body put the piece on ("" before); the panel shows it.
    arranged_place: StringProperty(name="Arranged On", options={"HIDDEN"})


classes = (TailorPieceSettings,)


def register() -> None:
    bpy.types.Object.tailor_piece = bpy.props.PointerProperty(type=TailorPieceSettings)


def unregister() -> None:
    del bpy.types.Object.tailor_piece
