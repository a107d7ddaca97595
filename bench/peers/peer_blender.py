"""Blender's Cloth modifier (the `bpy` wheel, headless) on an exported scene.

Knob: ``quality`` (Blender's "Quality Steps", solver steps per frame). The cloth is one mesh
with the scene's particles and triangles; its seams are loose edges between the sewn vertex
pairs with ``use_sewing_springs`` on; the body is a mesh object with a Collision modifier; the
pinned particles are a vertex group used as the pin group. Material mapping (see
docs/benchmarks.md, "Against peers"): Blender computes a structural spring's constant as
``k = tension / avg_spring_len`` (cloth.cc), and an isotropic triangle spring net has a 2D
stretch modulus of about ``2/sqrt(3) k``, so ``tension = sqrt(3)/2 * stretch * avg_edge``; shear
likewise from Tailor's shear; bending from Tailor's bend (both N m by the same reading); the
vertex mass is Blender's default 0.3 kg with every force parameter scaled to match (below).
"""

from __future__ import annotations

import math
import time

import numpy as np

import scenes

AIR_DAMPING = 0.2  # 1/s, Tailor's default air damping
BLENDER_MASS = 0.3  # kg per vertex, Blender's default


def cloth_object(sc, scene: dict, knob: dict, name: str = "cloth"):
    """Blender's Cloth on `scene`'s garment, linked into Blender scene `sc`: one mesh with the
    scene's particles (world space, in order) and triangles, its sewn pairs rounded to vertex
    pairs as loose edges with sewing springs on, its pins as the pin group (a `pin_weights`
    array beside `pinned` gives soft pins), material, air damping, thickness and
    self-collision mapped as the module doc says. Returns (object, Cloth modifier, vertex pairs).
    The caller sets the point cache's frames and adds the body (`collision_body`)."""
    import bpy

    pos, tris = scene["positions"], scene["triangles"]
    pairs = scenes.vertex_pairs(scene)
    mesh = bpy.data.meshes.new(name)
    mesh.from_pydata(pos.tolist(), pairs.tolist(), tris.tolist())
    mesh.update()
    loose = sum(1 for e in mesh.edges if e.is_loose)
    if (len(mesh.vertices), len(mesh.polygons), loose) != (len(pos), len(tris), len(pairs)):
        raise RuntimeError(f"Blender mesh has {len(mesh.vertices)} vertices / {len(mesh.polygons)} faces / {loose} "
                           f"seam edges, the scene {len(pos)} / {len(tris)} / {len(pairs)}")
    obj = bpy.data.objects.new(name, mesh)
    sc.collection.objects.link(obj)

    mod = obj.modifiers.new("Cloth", "CLOTH")
    cs, cc = mod.settings, mod.collision_settings
    cs.quality = int(knob["quality"])
    cs.time_scale = 1.0
    # Blender's cloth is tuned for vertex masses near its default of 0.3 kg: with the scene's real
    # masses (about 1e-4 kg) its implicit solve stops early and the cloth barely falls. Scaling
    # every mass and force parameter by the same factor leaves the motion unchanged, so the
    # vertex mass is 0.3 kg and the stiffnesses are multiplied by 0.3 kg / the mean mass.
    cs.mass = BLENDER_MASS
    lam = BLENDER_MASS / float(np.mean(scene["masses"]))
    edge = float(np.mean(scene["rest_lengths"]))
    k = math.sqrt(3.0) / 2.0 * edge * lam
    cs.tension_stiffness = cs.compression_stiffness = float(scene["stretch"]) * k
    cs.shear_stiffness = float(scene["shear"]) * k
    cs.bending_stiffness = float(scene["bend"]) * lam
    # Air drag is 0.01 * air_damping * v per vertex (cloth.cc): Tailor's rate times the mass.
    # The spring damping stays at Blender's defaults, which are relative to the 0.3 kg mass.
    cs.air_damping = 100.0 * AIR_DAMPING * BLENDER_MASS
    if len(scene["pinned"]):
        vg = obj.vertex_groups.new(name="pin")
        weights = scene.get("pin_weights")
        if weights is None:
            vg.add(scene["pinned"].tolist(), 1.0, "REPLACE")
        else:
            for w in np.unique(weights):
                vg.add(scene["pinned"][weights == w].tolist(), float(w), "REPLACE")
        cs.vertex_group_mass = "pin"
    if len(pairs):
        cs.use_sewing_springs = True
        # Unlimited (Blender's default). A cap of 20 g per vertex (59 N) left the shirt's seams
        # open (445 mm after 30 frames at quality 5), so the cap is not used.
        cs.sewing_force_max = 0.0
    cc.use_collision = bool(len(scene["body_triangles"]))
    cc.distance_min = float(scene["thickness"]) - 0.001
    cc.use_self_collision = bool(scene["self_collision"])
    cc.self_distance_min = float(scene["thickness"])
    return obj, mod, pairs


def collision_body(obj) -> None:
    """A Collision modifier on `obj` (after its deforming modifiers): 1 mm outer thickness, which
    with the cloth's `distance_min` (thickness - 1 mm) keeps the scene's thickness."""
    obj.modifiers.new("Collision", "COLLISION")
    obj.collision.thickness_outer = 0.001
    obj.collision.thickness_inner = 0.01


def run(scene: dict, knob: dict, cap: float = float("inf")) -> dict:
    import bpy

    t0 = time.perf_counter()
    bpy.ops.wm.read_factory_settings(use_empty=True)
    sc = bpy.context.scene
    frames = int(scene["frames"])
    sc.render.fps, sc.render.fps_base = int(round(float(scene["fps"]))), 1.0
    sc.frame_start, sc.frame_end = 1, frames + 1
    sc.gravity = tuple(float(g) for g in scene["gravity"])
    sc.use_gravity = True

    if len(scene["body_triangles"]):
        bmesh_ = bpy.data.meshes.new("body")
        bmesh_.from_pydata(scene["body_vertices"].tolist(), [], scene["body_triangles"].tolist())
        bmesh_.update()
        body = bpy.data.objects.new("body", bmesh_)
        sc.collection.objects.link(body)
        collision_body(body)
    obj, mod, pairs = cloth_object(sc, scene, knob)
    pos = scene["positions"]
    mod.point_cache.frame_start, mod.point_cache.frame_end = 1, frames + 1
    sc.frame_set(1)
    setup = time.perf_counter() - t0

    n = len(pos)
    co = np.empty(n * 3, np.float32)
    wall, cpu, nan_frame = [], [], None
    for f in range(2, frames + 2):
        if sum(wall[1:]) > cap:  # the first frame (Warp compiles its kernels there) does not count
            break
        w0, c0 = time.perf_counter(), time.process_time()
        sc.frame_set(f)
        wall.append(time.perf_counter() - w0)
        cpu.append(time.process_time() - c0)
        ev = obj.evaluated_get(bpy.context.evaluated_depsgraph_get())
        ev.data.vertices.foreach_get("co", co)
        if nan_frame is None and not np.isfinite(co).all():
            nan_frame = f - 1
    return dict(frame_wall_s=wall, frame_cpu_s=cpu, setup_s=setup, final=co.reshape(n, 3).copy(), nan_frame=nan_frame,
                version=f"Blender {bpy.app.version_string} (bpy wheel)", vertex_pairs=pairs)
