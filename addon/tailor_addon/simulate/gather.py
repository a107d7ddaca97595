"""Scene -> arrays for the simulation (main thread only): settings, fabric, maps, colliders.

Colliders are any mesh objects marked `tailor_collider.is_collider`, evaluated through the
depsgraph (armature, shape keys, Surface Deform...) in world space: one copy per frame with
`foreach_get`. Their triangles are read once, at the start frame: the topology must not
change over the range (`tailor.bake.check_collider_positions` says so when it does).
"""

from __future__ import annotations

import bpy
import numpy as np

from .. import preferences, scene_data
from ..core import AddonError
from ..core.simulate import ColliderData, PieceFabric, SimSettings
from ..paint.maps import collision_levels, painted_maps


def sim_settings(scene) -> SimSettings:
    s = scene.tailor_simulate
    return SimSettings(
        substeps=s.substeps,
        iterations=s.iterations,
        tolerance=s.tolerance,
        two_level=s.two_level,
        backend=preferences.backend(scene),
        threads=preferences.threads(),
        gravity=scene_gravity(scene),
        air_damping=s.air_damping,
        ramp_enabled=s.ramp_enabled,
        ramp_closing_speed=s.ramp_closing_speed,
        ramp_closing_damping=s.ramp_closing_damping,
        thickness=s.thickness,
        self_collision=s.self_collision,
        self_collision_radius=s.self_collision_radius,
        self_collision_contacts=s.self_collision_contacts,
        fps=scene.render.fps / scene.render.fps_base,
        seam_stiffness=s.seam_stiffness,
        seam_bend_stiffness=s.seam_bend_stiffness,
        friction_static=s.friction_static,
        friction_kinetic=s.friction_kinetic,
        pin_mode=s.pin_mode,
        pin_stiffness=s.pin_stiffness,
    )


def scene_gravity(scene) -> tuple[float, float, float]:
    """The scene's gravity (Scene Properties), zero when the scene's Gravity is off: what
    Blender's own physics use, so there is one gravity per scene."""
    return tuple(scene.gravity) if scene.use_gravity else (0.0, 0.0, 0.0)


def fabrics(objects) -> list[PieceFabric]:
    out = []
    for o in objects:
        p = o.tailor_piece
        directions = (p.stretch_v, p.bend_bias, p.bend_v) if p.anisotropic else (None, None, None)
        out.append(PieceFabric(p.density, p.stretch, p.shear, p.bend, *directions))
    return out


def collider_objects(scene) -> list:
    return sorted(
        (o for o in scene.objects if o.type == "MESH" and o.tailor_collider.is_collider and not o.tailor_piece.is_piece),
        key=lambda o: o.name,
    )


def _position_attribute(mesh):
    """The mesh's vertex positions as an attribute (Blender 3.5+), or None (3.4: the vertices' `co`)."""
    a = mesh.attributes.get("position")
    return a if a is not None and a.domain == "POINT" and a.data_type == "FLOAT_VECTOR" else None


def read_positions(mesh) -> np.ndarray:
    """A mesh's local vertex positions, flat float32. Through the `position` attribute: one
    copy, where `vertices.foreach_get("co")` goes vertex by vertex (Blender 4.5: 0.41 against
    0.004 ms for the sample body's 23,752 vertices, every Live frame); the same values."""
    co = np.empty(len(mesh.vertices) * 3, np.float32)
    a = _position_attribute(mesh)
    if a is not None:
        a.data.foreach_get("vector", co)
    else:
        mesh.vertices.foreach_get("co", co)
    return co


def write_positions(mesh, co: np.ndarray) -> None:
    """Writes flat float32 local vertex positions into a mesh (`read_positions`' way round:
    0.036 against 0.001 ms a piece); the caller tags it (`mesh.update()`)."""
    a = _position_attribute(mesh)
    if a is not None:
        a.data.foreach_set("vector", co)
    else:
        mesh.vertices.foreach_set("co", co)


def evaluated_positions(obj, depsgraph) -> np.ndarray:
    """(n, 3) float32 world-space vertex positions of `obj` with its modifiers at the
    depsgraph's frame."""
    ev = obj.evaluated_get(depsgraph)
    me = ev.to_mesh()
    try:
        co = read_positions(me)
    finally:
        ev.to_mesh_clear()
    m = np.array(ev.matrix_world, np.float64)
    return (co.reshape(-1, 3).astype(np.float64) @ m[:3, :3].T + m[:3, 3]).astype(np.float32)


def evaluated_triangles(obj, depsgraph) -> np.ndarray:
    ev = obj.evaluated_get(depsgraph)
    me = ev.to_mesh()
    try:
        me.calc_loop_triangles()
        tris = np.empty(len(me.loop_triangles) * 3, np.int32)
        me.loop_triangles.foreach_get("vertices", tris)
    finally:
        ev.to_mesh_clear()
    return tris.reshape(-1, 3)


def collider_data(objects, depsgraph) -> list[ColliderData]:
    out = []
    for o in objects:
        pos = evaluated_positions(o, depsgraph)
        levels = collision_levels(o)
        if levels is not None and len(levels) != len(pos):
            levels = None  # painted on the original mesh; a modifier changed the vertex count
        out.append(
            ColliderData(o.name, pos, evaluated_triangles(o, depsgraph), o.tailor_collider.friction_static,
                         o.tailor_collider.friction_kinetic, levels)
        )
    return out


def colliders_at(scene, objects, frame: int) -> list[np.ndarray]:
    """Every collider's world positions at scene frame `frame` (moves the scene there)."""
    if scene.frame_current != frame:
        scene.frame_set(frame)
    dg = bpy.context.evaluated_depsgraph_get()
    return [evaluated_positions(o, dg) for o in objects]


def rest_pose_positions(scene, objects) -> list[np.ndarray]:
    """Every collider's world positions with every armature of the scene in its rest pose
    (the pose sewing patterns are placed for); the armatures are put back after."""
    arms = [o.data for o in scene.objects if o.type == "ARMATURE" and o.data.pose_position != "REST"]
    try:
        for a in arms:
            a.pose_position = "REST"
        bpy.context.view_layer.update()
        dg = bpy.context.evaluated_depsgraph_get()
        return [evaluated_positions(o, dg) for o in objects]
    finally:
        for a in arms:
            a.pose_position = "POSE"
        bpy.context.view_layer.update()


def read_scene(scene):
    """(garment, piece objects, fabrics, maps, collider objects) for the scene's garment;
    raises `AddonError` when there is nothing to simulate."""
    s = scene.tailor_simulate
    garment_name = s.garment or None
    objects = scene_data.piece_objects(scene, garment_name)
    garment = scene_data.build_garment(scene, garment_name)
    colliders = collider_objects(scene)
    if not colliders:
        raise AddonError("no collider is marked", "Select the character and press Mark Collider (Simulate panel)")
    return garment, objects, fabrics(objects), [painted_maps(o) for o in objects], colliders
