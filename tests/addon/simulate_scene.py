"""The Simulate tests' scene: the sample character walking, the GarmentCode shirt imported
through the add-on and turned into the character's Z-up frame, an isotropic collider proxy.

Shared by tests/addon/test_simulate*.py and the add-on benchmarks (bench_simulate.py;
bench_garments.py through cloth_scene.py)."""

from __future__ import annotations

import math
from pathlib import Path

import bpy
from mathutils import Matrix

ROOT = Path(__file__).resolve().parents[2]
CHARACTER = ROOT / "sample_blends" / "character.blend"
SHIRT = ROOT / "native" / "tailor-core" / "tests" / "data" / "garmentcode" / "shirt_mean_specification.json"
#: GarmentCode places its patterns Y-up; the sample character is Z-up (x, y, z) -> (x, -z, y).
Y_UP_TO_Z_UP = Matrix.Rotation(math.radians(90.0), 4, "X")
#: As imported, the shirt's top edge is at 1.40 m: GarmentCode places its shoulder seams 3-6 cm
#: below this body's shoulder line, so they close through the shoulders. Lifted 4 cm (what
#: sample_blends/build/garments.py picks for the sample T-shirt: the smallest lift with no torso
#: seam closing through the body) it closes over the shoulders, without gravity (the add-on's
#: assembly), and hangs there. Lifted 14 cm (this scene's earlier placement, from before
#: gravity waited for the seams) its seams close above the shoulders, round the neck, and with
#: seams at 1e4 N/m it drops onto them bunched like a scarf (tests/addon/diagnose_bake.py).
LIFT = 0.04
#: The T-shirt sample's pins (sample_blends/build/garments.py): the top 4 cm of the torso
#: panels, their shoulder lines, which ride on the body once the seams have met. Without them
#: the shirt is dragged down the body by the arms coming down from the A-pose (measured with
#: tests/addon/diagnose_bake.py: its top from 1.44 m to 1.09 m over the 40-frame transition,
#: strain up to 2), as a sewn shirt with no pins does on the samples too.
PIN_PIECES, PIN_BAND = ("ftorso", "btorso"), 0.04


def shirt_on_character(blend_path: Path, edge: float = 0.03, proxy_voxel: float | None = 0.02,
                       frames: tuple[int, int] = (1, 4), preroll: int | None = None,
                       lift: float = LIFT, pins: bool = True) -> dict:
    """Opens the character, imports the shirt, paints its shoulder lines as pins (`pins`),
    marks the collider (a proxy when `proxy_voxel`), sets the bake range and saves the file as
    `blend_path` (caches go beside it)."""
    bpy.ops.wm.open_mainfile(filepath=str(CHARACTER))
    scene = bpy.context.scene
    before = set(bpy.data.objects)
    assert bpy.ops.tailor.import_pattern(filepath=str(SHIRT), edge_length=edge) == {"FINISHED"}
    pieces = sorted((o for o in bpy.data.objects if o not in before), key=lambda o: o.name)
    # Importers that keep GarmentCode's Y-up put the shirt's height on Y (its Z centred on 0).
    y_up = sum(o.matrix_world.translation.z for o in pieces) / len(pieces) < 0.5
    for o in pieces:
        o.matrix_world = Matrix.Translation((0.0, 0.0, lift)) @ (Y_UP_TO_Z_UP if y_up else Matrix()) @ o.matrix_world
    if pins:
        paint_pins(pieces)
    body = bpy.data.objects["Body"]
    collider = mark_collider(scene, body, proxy_voxel)
    s = scene.tailor_simulate
    scene.frame_start, scene.frame_end = frames
    if preroll is not None:  # else the panel's default (60 frames, then a 40-frame transition)
        s.preroll = preroll
    scene.frame_set(frames[0])
    bpy.ops.wm.save_as_mainfile(filepath=str(blend_path))
    return {"scene": scene, "pieces": pieces, "body": body, "collider": collider}


def paint_pins(pieces) -> int:
    """Pins the top PIN_BAND of the torso panels as an artist does: the vertices selected in
    Edit Mode, then the Paint panel's Set Painted Value. Returns how many were pinned."""
    import numpy as np

    pinned = 0
    view_layer = bpy.context.view_layer
    for o in pieces:
        if not o.tailor_piece.piece_name.endswith(PIN_PIECES):
            continue
        z = np.array([(o.matrix_world @ v.co).z for v in o.data.vertices])
        sel = z >= z.max() - PIN_BAND
        for other in view_layer.objects:
            other.select_set(other == o)
        view_layer.objects.active = o
        o.data.vertices.foreach_set("select", sel)
        bpy.ops.object.mode_set(mode="EDIT")
        assert bpy.ops.tailor.paint_set(map="PIN", value=1.0, only_selected=True) == {"FINISHED"}
        bpy.ops.object.mode_set(mode="OBJECT")
        o.data.vertices.foreach_set("select", np.zeros(len(sel), bool))
        pinned += int(sel.sum())
    assert pinned > 0, "no torso panel found to pin"
    return pinned


def mark_collider(scene, body, proxy_voxel: float | None = None):
    """Marks `body` as the collider with the add-on's operator, or makes its isotropic proxy
    (voxel size `proxy_voxel`) and lets that collide instead; returns the collider object."""
    for o in scene.objects:
        o.select_set(o == body)
    bpy.context.view_layer.objects.active = body
    assert bpy.ops.tailor.mark_collider() == {"FINISHED"}
    if not proxy_voxel:
        return body
    assert bpy.ops.tailor.collider_proxy(voxel_size=proxy_voxel) == {"FINISHED"}
    return bpy.data.objects[f"{body.name}_collider"]
