"""Simulate settings: `Scene.tailor_simulate` (the panel) and `Object.tailor_collider`."""

from __future__ import annotations

import bpy
from bpy.props import (
    BoolProperty,
    EnumProperty,
    FloatProperty,
    IntProperty,
    PointerProperty,
    StringProperty,
)

import tailor
from tailor import bake

from ..core import fit_maps
from ..core.simulate import PRESETS, preset_values
from . import garment_choice
from ..compat import BLEND_RELATIVE_PATH
from ..preferences import BACKENDS

# Every default below is the module's (one source: tailor-core): the defaults of its settings,
# its Final preset (the panel opens in Final), and the garment setup's defaults.
_SETTINGS = tailor.Settings()
_FINAL = tailor.Settings.preset("final")
_SETUP = tailor.DEFAULT_SETUP


FRICTION_HELP = "The cloth's, where not painted: against itself (Self-Collision); painted values also against colliders"


def _apply_preset(self, _context) -> None:
    if self.preset in PRESETS:
        v = preset_values(self.preset)
        self.substeps, self.iterations, self.tolerance = v["substeps"], v["iterations"], v["tolerance"]


class TailorColliderSettings(bpy.types.PropertyGroup):
    is_collider: BoolProperty(
        name="Collider",
        description="The garment collides with this mesh, evaluated with its modifiers (armature, "
        "shape keys) at every frame",
        default=False,
    )
    friction_static: FloatProperty(name="Static Friction", min=0.0, default=0.5)
    friction_kinetic: FloatProperty(name="Kinetic Friction", min=0.0, default=0.3)
    proxy_of: PointerProperty(
        name="Proxy Of", type=bpy.types.Object, description="The mesh this isotropic collider proxy follows"
    )
    # Triangle-size spread (edge-length coefficient of variation, 95th/5th percentile ratio)
    # of the source and of this proxy, shown in the panel.
    spread_source_cv: FloatProperty(name="Source Edge CV", precision=3)
    spread_source_ratio: FloatProperty(name="Source Edge p95/p5", precision=2)
    spread_proxy_cv: FloatProperty(name="Proxy Edge CV", precision=3)
    spread_proxy_ratio: FloatProperty(name="Proxy Edge p95/p5", precision=2)


class TailorSimulateSettings(bpy.types.PropertyGroup):
    garment: StringProperty(
        name="Garment", description="Simulate only this garment (collection name); empty: every piece of the scene"
    )
    garment_choice: EnumProperty(
        name="Garment", description="Simulate one of the scene's garments, or every piece",
        items=garment_choice.items, get=garment_choice.get_number, set=garment_choice.set_number,
    )
    preset: EnumProperty(
        name="Quality",
        items=(
            ("PREVIEW", "Preview", "Fewer substeps and iterations: interactive Live mode"),
            ("FINAL", "Final", "The quality the bake is checked at"),
            ("CUSTOM", "Custom", "Substeps, iterations and tolerance as set below"),
        ),
        default="FINAL",
        update=_apply_preset,
    )
    substeps: IntProperty(name="Substeps", description="Solver substeps per frame", min=0, soft_min=1,
                          default=_FINAL.substeps)
    iterations: IntProperty(name="Iterations", description="Solver iterations per substep", min=1,
                            default=_FINAL.iterations)
    tolerance: FloatProperty(
        name="Tolerance", description="Relative residual at which iterations stop early (0: run them all)",
        min=0.0, default=_FINAL.tolerance,
        precision=6,
    )
    two_level: BoolProperty(
        name="Two-Level Solve",
        description="After each sweep, correct the smooth part of the error on a coarse grid, so that bending and "
        "the garment's large-scale stretch converge (stiffer, truer drape; about 1.2-1.5x the frame time on the "
        "CPU; also runs on the GPU). Not applied while self-collision is on",
        default=False,
    )
    # Numbered: files saved before "Preferences" was added keep their Auto/CPU/GPU.
    backend: EnumProperty(
        name="Backend",
        items=(("PREFERENCES", "Preferences", "The add-on preferences' backend (Edit > Preferences > Add-ons)", 3),)
        + BACKENDS,
        default="PREFERENCES",
    )
    adapter: StringProperty(name="Adapter", description="The adapter the last simulation ran on")
    air_damping: FloatProperty(
        name="Air Damping", description="Velocity damping per second once the seams are closed", min=0.0,
        default=_SETTINGS.air_damping, precision=3,
    )
    ramp_enabled: BoolProperty(
        name="Seam Closing Ramp", description="Raise damping while the seams close (paper Sec. 4)", default=True
    )
    ramp_closing_speed: FloatProperty(
        name="Closing Speed", description="Speed at which seams close, m/s (0: at once)", min=0.0,
        default=_SETTINGS.ramp_closing_speed, unit="VELOCITY",
    )
    ramp_closing_damping: FloatProperty(
        name="Closing Damping", description="Damping while the seams close", min=0.0,
        default=_SETTINGS.ramp_closing_damping, precision=3,
    )
    thickness: FloatProperty(
        name="Thickness", description="Collision thickness: distance kept from colliders", min=0.0,
        default=_SETUP["thickness"],
        subtype="DISTANCE", unit="LENGTH", precision=4,
    )
    self_collision: BoolProperty(
        name="Self-Collision", description="Cloth against itself (layered garments; fights closing seams)",
        default=False,
    )
    self_collision_contacts: EnumProperty(
        name="Contacts", description="What the cloth collides with itself by",
        items=(
            ("SPHERES", "Spheres", "A sphere round each particle, pairs pushed apart (the paper's model; a thick shell "
             "that keeps layers apart but holds seams open)"),
            ("TRIANGLES", "Triangles", "Each particle kept off the cloth's triangles on the side it was on, so it "
             "cannot pass through between iterations (CPU only)"),
        ),
        default="SPHERES",
    )
    self_collision_radius: FloatProperty(
        name="Radius", description="Spheres: the radius of each particle's sphere (0: half the mean edge length); "
        "smaller lets layers lie closer, much under half an edge lets them pass between particles. Triangles: the "
        "distance kept from a triangle (0: 4 mm)", min=0.0, default=0.0, subtype="DISTANCE", unit="LENGTH",
        precision=4,
    )
    seam_stiffness: FloatProperty(name="Seam Stiffness", description="N/m, times each seam's factor", min=0.0,
                                  default=_SETUP["seam_stiffness"])
    seam_bend_stiffness: FloatProperty(name="Seam Bending", min=0.0, default=_SETUP["seam_bend_stiffness"],
                                       precision=6)
    # The cloth's friction (the garment setup's `friction`).
    friction_static: FloatProperty(name="Static Friction", description=FRICTION_HELP, min=0.0,
                                   default=_SETUP["friction"]["static"])
    friction_kinetic: FloatProperty(name="Kinetic Friction", description=FRICTION_HELP, min=0.0,
                                    default=_SETUP["friction"]["kinetic"])
    pin_mode: EnumProperty(
        name="Pins",
        items=(
            ("ATTACH", "Ride on Character", "Painted pins are attached to the (first) collider once the seams have "
             "met, and follow the body as it moves"),
            ("FIXED", "Fixed in Place", "Painted pins stay where they were placed, in world space, from the first "
             "frame (they can hold seams open)"),
        ),
        default="ATTACH",
    )
    pin_stiffness: FloatProperty(
        name="Pin Stiffness", description="N/m per pinned vertex riding on the character, times its painted weight",
        min=0.0, soft_min=1.0, default=_SETUP["pin_stiffness"],
    )
    # Bake
    use_scene_range: BoolProperty(name="Scene Range", description="Bake the scene's frame range", default=True)
    frame_start: IntProperty(name="Start", default=1)
    frame_end: IntProperty(name="End", default=48)
    preroll: IntProperty(
        name="Preroll", description="Frames solved at the start frame before it is recorded (the garment "
        "assembles first; more while its seams are still closing, up to 10 s)", min=0, default=bake.DEFAULT_PREROLL,
    )
    assemble_at_rest: BoolProperty(
        name="Assemble at Rest Pose", description="Assemble during the preroll with every armature in its rest "
        "pose (patterns are placed for it), then move the colliders into the start frame's pose",
        default=True,
    )
    assemble_without_gravity: BoolProperty(
        name="Assemble Without Gravity", description="No gravity during the preroll: while its seams are open "
        "the garment has nothing to hang on and would slide off the body",
        default=True,
    )
    transition: IntProperty(
        name="Transition", description="Frames moving the colliders from the rest pose to the start frame's",
        min=0, default=bake.DEFAULT_TRANSITION,
    )
    cache_dir: StringProperty(
        name="Cache Folder", description="Where PC2 caches go (// = beside the .blend); empty: the add-on "
        "preferences' folder", default="", subtype="DIR_PATH", options=BLEND_RELATIVE_PATH,
    )
    cache_mode: EnumProperty(
        name="Cache",
        items=(
            ("PIECE", "Per Piece", "One PC2 per piece, played on the piece by a Mesh Cache modifier"),
            ("GARMENT", "Per Garment", "One PC2 for the whole garment, played on a joined garment object"),
        ),
        default="PIECE",
    )
    # Last bake (display)
    baked_frames: IntProperty(name="Baked Frames", default=0)
    bake_report: StringProperty(name="Last Bake", description="Summary of the last bake's quality")
    baked_fit_maps: StringProperty(
        name="Baked Fit Maps", description="The last bake's fit maps (kept when a Fit Map was chosen), shown per frame",
        default="", subtype="FILE_PATH",
    )
    # Live
    live_running: BoolProperty(name="Live", default=False, options={"SKIP_SAVE"})
    show_overlay: BoolProperty(name="Overlay", description="Draw fps, seam gap, penetrations, strain", default=True)
    fit_map: EnumProperty(
        name="Fit Map",
        description="Colour the pieces by a fit map while Live runs (refreshed a few times a second, with the "
        "overlay's figures): the maps are written as point attributes tailor_strain, tailor_pressure and "
        "tailor_distance, the colours as the colour attribute tailor_fit_map (Viewport Shading: Attribute)",
        items=[("NONE", "None", "No fit map")] + [(i, label, what) for i, label, _key, what in fit_maps.MAPS],
        default="NONE",
    )
    show_fit_map_overlay: BoolProperty(
        name="Fit Map Overlay",
        description="Draw the fit map's colours over the pieces in the 3D view, in any shading mode",
        default=True,
    )


classes = (TailorColliderSettings, TailorSimulateSettings)


def register() -> None:
    bpy.types.Object.tailor_collider = PointerProperty(type=TailorColliderSettings)
    bpy.types.Scene.tailor_simulate = PointerProperty(type=TailorSimulateSettings)


def unregister() -> None:
    del bpy.types.Scene.tailor_simulate
    del bpy.types.Object.tailor_collider
