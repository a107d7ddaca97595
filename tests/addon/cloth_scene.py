"""A sample garment on the walking character, set up once for Tailor and for Blender's Cloth.

Shared by the add-on benchmark (`bench_garments.py`) and its smoke test (`test_cloth_scene.py`).

`walking_scene` opens `sample_blends/NAME.blend` (character and garment made with the add-on,
rig in its rest pose), marks the collider, takes thickness and self-collision from the sample's
garment file (`settings.tailor_sample`), turns the rig's pose on and moves the walk so that
both simulators get the same schedule:

* frames `1 .. start - transition`: rest pose, the pose the patterns are placed for (Tailor's
  bake: `preroll` steps at the rest pose, under no gravity);
* frames `start - transition .. start`: the rig moves from the rest pose into the walk's first
  pose (Tailor's bake: `transition` steps moving the collider from rest to the start pose);
* frames `start .. start + frames - 1`: the walk, recorded by both.

Tailor's bake does the first two stages itself (`tailor.bake.Bake`), so its scene range is the
recorded frames. Blender's Cloth (`blender_cloth`) simulates from frame 1 with the same pose
keys and gravity keyed off over the preroll, the usual way to sew in Blender: the cloth is the
pieces joined into one mesh with the seams as loose edges and sewing springs on
(`bench/peers/peer_blender.cloth_object`, the same mapping as the module-level peer benchmark),
the body a Collision modifier object.
"""

from __future__ import annotations

import json
import sys
from importlib import import_module
from pathlib import Path

import bpy
import numpy as np

from simulate_scene import mark_collider

ROOT = Path(__file__).resolve().parents[2]
SAMPLES = ROOT / "sample_blends"
PEERS = ROOT / "bench" / "peers"
MODULE = "bl_ext.user_default.tailor_addon"
BODY = "Body"
RIG = "Rig"
PIN_GROUP = "tailor_pin"  # the add-on's painted pin map (`core/paint.py`)


def peers():
    """`bench/peers`'s `peer_blender`, `scenes` and `metrics` modules (they import `tailor`, so
    only once the add-on is installed)."""
    if str(PEERS) not in sys.path:
        sys.path.insert(0, str(PEERS))
    return import_module("peer_blender"), import_module("scenes"), import_module("metrics")


def sample_settings(name: str) -> dict:
    """The sample's own simulation settings (thickness, self-collision, per-piece fabric)."""
    return json.loads((SAMPLES / f"{name}.json").read_text())["settings"]["tailor_sample"]


def _fcurves(action):
    """The action's F-curves (Blender 4.4+ keeps them in a layered action's channel bags)."""
    if hasattr(action, "fcurves"):
        return list(action.fcurves)
    return [fc for layer in action.layers for strip in layer.strips for bag in strip.channelbags for fc in bag.fcurves]


def _rest_value(data_path: str, index: int) -> float:
    if data_path.endswith("rotation_quaternion"):
        return 1.0 if index == 0 else 0.0
    if data_path.endswith("scale"):
        return 1.0
    return 0.0  # location, Euler rotation


def walk_with_assembly(rig, start: int, transition: int) -> None:
    """Moves the rig's active action so that its first frame plays at `start`, and keys the
    rest pose at `start - transition` (held before it)."""
    action = rig.animation_data.action
    first = action.frame_range[0]
    shift = start - first
    for fc in _fcurves(action):
        for kp in fc.keyframe_points:
            kp.co.x += shift
            kp.handle_left.x += shift
            kp.handle_right.x += shift
        fc.update()
        if transition > 0:
            kp = fc.keyframe_points.insert(start - transition, _rest_value(fc.data_path, fc.array_index))
            kp.interpolation = "LINEAR"
    rig.data.pose_position = "POSE"


def walking_scene(name: str, blend_path: Path, frames: int = 24, preroll: int = 60, transition: int = 40,
                  proxy_voxel: float | None = None, preset: str = "FINAL", unpin: bool = False) -> dict:
    """Opens sample `name`, sets it up as the module doc says and saves it as `blend_path`;
    with `unpin`, without the painted pins (the `tailor_pin` vertex group: weight 1 pins a
    vertex in place, so a seam between two pinned bands cannot close). Returns the frame
    numbers and the collider's name."""
    bpy.ops.wm.open_mainfile(filepath=str(SAMPLES / f"{name}.blend"))
    scene = bpy.context.scene
    start = 1 + preroll + transition
    walk_with_assembly(bpy.data.objects[RIG], start, transition)
    scene.frame_set(1)  # the rest pose (a proxy binds to the body as the pieces were placed)
    collider = mark_collider(scene, bpy.data.objects[BODY], proxy_voxel)
    if unpin:
        for o in scene.objects:
            vg = o.vertex_groups.get(PIN_GROUP) if o.type == "MESH" and o.tailor_piece.is_piece else None
            if vg is not None:
                o.vertex_groups.remove(vg)
    spec = sample_settings(name)
    s = scene.tailor_simulate
    s.preset = preset
    s.thickness = float(spec["thickness"])
    s.self_collision = bool(spec["self_collision"])
    s.self_collision_radius = float(spec.get("self_collision_radius", 0.0))
    s.friction_static = float(spec.get("friction_static", s.friction_static))
    s.friction_kinetic = float(spec.get("friction_kinetic", s.friction_kinetic))
    s.preroll, s.transition = preroll, transition
    s.use_scene_range = True
    scene.frame_start, scene.frame_end = start, start + frames - 1
    scene.frame_set(start)
    bpy.ops.wm.save_as_mainfile(filepath=str(blend_path))
    return {"start": start, "end": start + frames - 1, "first": 1, "collider": collider.name,
            "gravity_off_until": start - transition}


def garment_arrays(scene, name: str) -> tuple[dict, list]:
    """The garment as the add-on builds it (`simulate.gather` + `core.simulate.build`: pieces in
    order, seams, per-piece fabric, pins), exported as the peer benchmark's plain arrays
    (`bench/peers/scenes.export`) with the sample's fabric, thickness and self-collision.
    Returns (arrays, piece objects)."""
    _, scenes, _ = peers()
    gather = import_module(MODULE + ".simulate.gather")
    core_sim = import_module(MODULE + ".core.simulate")
    garment, objects, fabrics, maps, colliders = gather.read_scene(scene)
    dg = bpy.context.evaluated_depsgraph_get()
    built = core_sim.build(garment, gather.sim_settings(scene), fabrics, maps, gather.collider_data(colliders, dg))
    groups = built.garment.pin_weights()  # [(weight, particles)], weight 1 first
    pinned = np.concatenate([np.zeros(0, np.int64)] + [p for _, p in groups]).astype(np.int64)
    weights = np.concatenate([np.zeros(0)] + [np.full(len(p), w) for w, p in groups]).astype(np.float32)
    body = bpy.data.objects[BODY]
    bv = gather.evaluated_positions(body, dg)
    bt = gather.evaluated_triangles(body, dg)
    fps = scene.render.fps / scene.render.fps_base
    arrays = scenes.export(name, built.sim, pinned, bv, bt, gather.scene_gravity(scene), 0)
    f0 = fabrics[0]  # Blender's Cloth takes one material per object; Tailor takes the first piece's bending too
    s = scene.tailor_simulate
    arrays.update(density=np.float32(f0.density), stretch=np.float32(f0.stretch), shear=np.float32(f0.shear),
                  bend=np.float32(f0.bend), thickness=np.float32(s.thickness), fps=np.float32(fps),
                  self_collision=np.bool_(s.self_collision), pin_weights=weights,
                  self_collision_radius=np.float32(s.self_collision_radius),
                  fabrics_differ=len({(f.stretch, f.shear, f.bend) for f in fabrics}) > 1)
    return arrays, objects


def blender_cloth(scene, arrays: dict, setup: dict, quality: int = 5):
    """Blender's Cloth on the garment (`arrays`, from `garment_arrays`) in `scene` as
    `walking_scene` left it: the joined pieces with seams as loose edges and sewing springs,
    the collider as a Collision object, the point cache over frames 1 .. end, gravity off until
    the transition starts. The add-on's pieces are hidden. Returns (object, Cloth modifier,
    vertex pairs)."""
    peer_blender, _, _ = peers()
    for o in scene.objects:
        if o.type == "MESH" and o.tailor_piece.is_piece:
            o.hide_set(True)
            o.hide_viewport = True
    obj, mod, pairs = peer_blender.cloth_object(scene, arrays, {"quality": quality}, name="Blender Cloth")
    peer_blender.collision_body(bpy.data.objects[setup["collider"]])
    cache = mod.point_cache
    cache.frame_start, cache.frame_end = setup["first"], setup["end"]
    scene.frame_start, scene.frame_end = setup["first"], setup["end"]
    w = mod.settings.effector_weights
    off = setup["gravity_off_until"]
    w.gravity = 0.0
    w.keyframe_insert("gravity", frame=off)
    w.gravity = 1.0
    w.keyframe_insert("gravity", frame=off + 1)
    for fc in _fcurves(obj.animation_data.action):
        for kp in fc.keyframe_points:
            kp.interpolation = "CONSTANT"
    scene.frame_set(setup["first"])
    return obj, mod, pairs


def evaluated_vertices(obj) -> np.ndarray:
    """(n, 3) float32 world positions of `obj`'s evaluated mesh (the cloth: identity transform)."""
    ev = obj.evaluated_get(bpy.context.evaluated_depsgraph_get())
    co = np.empty(len(ev.data.vertices) * 3, np.float32)
    ev.data.vertices.foreach_get("co", co)
    m = np.array(ev.matrix_world, np.float64)
    return (co.reshape(-1, 3).astype(np.float64) @ m[:3, :3].T + m[:3, 3]).astype(np.float32)
