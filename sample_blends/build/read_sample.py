"""Reads a sample .blend's garment into arrays for the module (bpy; used by tests/test_samples.py).

    .venv/bin/python sample_blends/build/read_sample.py SAMPLE.blend OUT.npz

Registers the add-on from addon/ (its properties hold the pieces and seams), opens the file and
writes with the add-on's own reader (`scene_data.build_garment`): world (Z-up) positions, rest
shapes, triangles and seam pairs of the garment; each piece's fabric and painted collision
levels and pins; the body's rest vertices, triangles and collision levels.
"""

import json
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "addon"))

import bpy  # noqa: E402
import numpy as np  # noqa: E402

import tailor_addon  # noqa: E402


def main(blend: str, out: str) -> None:
    from tailor_addon import scene_data
    from tailor_addon.core.paint import LEVEL_ATTR
    from tailor_addon.paint.maps import painted_maps

    bpy.ops.wm.open_mainfile(filepath=blend)
    scene = bpy.context.scene
    g = scene_data.build_garment(scene)
    objs = scene_data.piece_objects(scene)
    arrays = {"positions": g.positions, "rest": g.rest, "triangles": g.triangles, "offsets": g.offsets}
    seams = []
    for k in range(len(g.seams)):
        av, aw, bv, bw = g.seam_pairs(k)
        arrays.update({f"seam{k}_av": av, f"seam{k}_aw": aw, f"seam{k}_bv": bv, f"seam{k}_bw": bw})
        seams.append(g.seams[k].name)
    levels = np.zeros(len(g.positions), np.int32)
    pins = np.zeros(len(g.positions), np.float32)
    fabrics = []
    for o, off in zip(objs, g.offsets):
        p = o.tailor_piece
        fabrics.append({"density": p.density, "stretch": p.stretch, "shear": p.shear, "bend": p.bend})
        maps = painted_maps(o)
        n = len(o.data.vertices)
        if "collision_level" in maps:
            levels[off:off + n] = maps["collision_level"][0]
        if "pin" in maps:
            values, painted = maps["pin"]
            pins[off:off + n] = np.where(painted, values, 0.0)
    body = bpy.data.objects["Body"]
    me = body.data
    bv = np.empty(len(me.vertices) * 3, np.float32)
    me.vertices.foreach_get("co", bv)
    me.calc_loop_triangles()
    bt = np.empty(len(me.loop_triangles) * 3, np.int32)
    me.loop_triangles.foreach_get("vertices", bt)
    body_levels = scene_data.point_attribute(me, LEVEL_ATTR, np.int32)
    arrays.update(levels=levels, pins=pins, body=bv.reshape(-1, 3), body_triangles=bt.reshape(-1, 3),
                  body_levels=body_levels if body_levels is not None else np.zeros(len(me.vertices), np.int32))
    meta = {"seams": seams, "fabrics": fabrics, "pieces": [o.name for o in objs],
            "pose_position": bpy.data.objects["Rig"].data.pose_position, "frame_rate": scene.render.fps,
            "simulate": {k: getattr(scene.tailor_simulate, k) for k in ("thickness", "self_collision",
                                                                       "self_collision_radius",
                                                                       "friction_static", "friction_kinetic")}}
    np.savez(out, meta=json.dumps(meta), **arrays)


if __name__ == "__main__":
    tailor_addon.register()
    try:
        main(sys.argv[1], sys.argv[2])
    finally:
        tailor_addon.unregister()  # bpy 4.5 hangs at exit while operator classes are registered
