"""Builds the sample garments on the sample character: sample_blends/{tshirt,skirt,trousers,layered}.blend
and, beside each, its garment file (NAME.json + NAME.bin) for the headless module.

    .venv/bin/python sample_blends/build/garments.py [--only tshirt,skirt] [--edge 0.02]

For each garment, with the add-on's own operators (the add-on package is imported from addon/
and registered, as Blender does when it is enabled):

1. character.blend is opened; the rig is shown in its rest pose, where GarmentCode places its
   panels (Armature > Pose Position: Pose plays the walk);
2. each GarmentCode pattern of the garment is imported (`tailor.import_pattern`: pieces,
   placements, stitches as seams); pieces the garment does not use are deleted with their seams
   (the trousers are the jumpsuit's four trouser panels);
3. the importer turns the pieces from GarmentCode's Y-up frame into the character's Z-up frame
   (its "Y Up" option: the turn the body got, (x, y, z) -> (x, -z, y)); an outer layer is moved
   out from the body first;
4. each layer is lifted by the smallest of LIFTS that leaves fewest torso seams closing through
   the body (the layered outfit's two layers are lifted and their torso panels wrapped round
   the body's sides together: `wrap_torso`); sleeves and trouser legs are bent (`tailor.bend`)
   around the limb between their front and back panels by the angle among BEND_ANGLES with no
   vertex inside the body and at most MAX_BEND_STRAIN stretch, fewest seams closing through the
   limb, then the smallest gap (measured, printed; 0 keeps GarmentCode's flat placement);
5. collision levels are painted (`tailor.collision_level_set`): on the trousers, the left leg 3
   and the right leg 4, and on the body the arms 1 and 2 and the legs 3 and 4, from the skin
   weights; so trousers never catch on the arms and each trouser leg ignores the other leg;
6. fabric parameters are set per piece; the .blend is saved (relative paths, compressed);
7. the garment file is written from the scene (pieces with their placement in the glTF's Y-up
   frame, bends, seams, fabric and levels as the typed setup and per-particle
   parameters) and checked: `tailor.Garment.load(...).build_simulation()` must give the scene's
   piece positions, turned to Y-up, within 0.01 mm.

Whether each garment assembles on the character is checked by check_garments.py (module only).
"""

from __future__ import annotations

import argparse
import json
import math
import sys
import tempfile
from dataclasses import dataclass, field
from pathlib import Path

HERE = Path(__file__).resolve().parent
SAMPLES = HERE.parent
ROOT = SAMPLES.parent
PATTERNS = ROOT / "native" / "tailor-core" / "tests" / "data" / "garmentcode"
sys.path.insert(0, str(ROOT / "addon"))

try:
    import bpy
    from mathutils import Matrix, Vector
except ImportError:
    sys.exit('garments.py needs the bpy wheel: .venv/bin/pip install "bpy==4.5.*" (Python 3.11)')

import numpy as np

import tailor
from tailor_addon.core.garment import SeamData
from tailor_addon.core.simulate import SimSettings

# GarmentCode and glTF are Y-up facing +Z; the character is Z-up facing -Y.
Y_TO_Z = Matrix.Rotation(math.radians(90.0), 4, "X")
Z_TO_Y = Y_TO_Z.inverted()
BEND_ANGLES = (0.0, 15.0, 30.0, 45.0, 60.0, 90.0)
MAX_BEND_STRAIN = 0.10  # a bend that stretches the piece more than this snaps back at the start
LIFTS = (0.0, 0.02, 0.04, 0.06, 0.08, 0.10)  # metres a layer may be raised so its seams close outside
LIMB_PAIRS = (("sleeve_f", "sleeve_b"), ("pant_f", "pant_b"))
# The layered outfit's torso panels are wrapped round the body's sides (`Layer.wrap`, see
# `wrap_torso`): lifts and wrap angles tried together, and the most a wrap may stretch a panel.
WRAP_LIFTS = tuple(k / 100.0 for k in range(11))
WRAP_ANGLES = (0.0, 15.0, 30.0, 40.0, 45.0, 60.0)
MAX_WRAP_STRAIN = 0.25
TORSO_PAIRS = (("left_ftorso", "left_btorso"), ("right_ftorso", "right_btorso"))

# Fabrics (density kg/m^2, stretch and shear N/m, bend): light knit, woven cotton, light woven
# (skirt) and a heavier fleece for the hoody. Stiffer than real cloth in stretch: the solver's
# strain stays small at 8 substeps x 15 iterations.
JERSEY = dict(density=0.15, stretch=600.0, shear=60.0, bend=2e-5)
COTTON = dict(density=0.20, stretch=900.0, shear=90.0, bend=5e-5)
VOILE = dict(density=0.10, stretch=500.0, shear=50.0, bend=1e-5)
# The fleece bends like the jersey: every layered figure up to 2026-11-22 was made with 2e-5 for
# all pieces (the module then took the first piece's bending for the whole garment); with
# bending set per piece, the fleece's 1e-4 held the hoody's nape and shoulder seams open (seam
# gap median 4.7 mm over 30 frames at rest against 1.5; 5e-5: 2.7). With the hood sewn the right
# way round, 1e-4 no longer holds them open but still does worse at rest than 2e-5 (frames 6-11
# after all seams meet 0.80 / 1.04 mm against 0.51 / 0.70; a frame of 1.39 in 60).
FLEECE = dict(density=0.28, stretch=800.0, shear=80.0, bend=2e-5)


@dataclass
class Layer:
    pattern: str  # GarmentCode specification, without _specification.json
    fabric: dict
    colour: tuple[float, float, float]
    keep: tuple[str, ...] | None = None  # piece names kept (None: all)
    push_out: float = 0.0  # metres each piece is moved away from the body (outer layers)
    levels: dict[str, int] = field(default_factory=dict)  # piece name prefix -> collision level
    # piece name prefix -> band (metres from the top of the piece's rest shape; inf: all of it)
    # painted with pin weight 1: attached to the body (a waistband, a shoulder line)
    pins: dict[str, float] = field(default_factory=dict)
    # wrap the front/back torso panels round the body's sides (`wrap_torso`) instead of lifting
    # the flat layer only (`lift_clear_of_body`)
    wrap: bool = False


@dataclass
class Sample:
    name: str
    layers: list[Layer]
    body_levels: bool = False  # paint the body's arms and legs
    self_collision: bool = False  # layered garments collide with themselves
    # self-collision sphere radius, metres (0: the solver's half mean edge, 1 cm at 2 cm edges)
    self_collision_radius: float = 0.0
    thickness: float = 0.004
    edge: float = 0.02  # piece resolution, metres
    # the cloth's friction (static, kinetic): the Simulation panel's, also against itself
    friction: tuple[float, float] = (SimSettings.friction_static, SimSettings.friction_kinetic)


SHOULDERS = {"left_ftorso": 0.04, "right_ftorso": 0.04, "left_btorso": 0.04, "right_btorso": 0.04}
PANTS = ("pant_f_l", "pant_b_l", "pant_f_r", "pant_b_r")
SAMPLES_SPEC = [
    Sample("tshirt", [Layer("shirt_mean", JERSEY, (0.10, 0.35, 0.75), pins=SHOULDERS)]),
    Sample("skirt", [Layer("flare_skirt", VOILE, (0.70, 0.12, 0.22), pins={"wb_": math.inf})]),
    Sample(
        "trousers",
        [Layer("js_mean_all", COTTON, (0.18, 0.22, 0.32), keep=PANTS, levels={"pant_f_l": 3, "pant_b_l": 3,
                                                                              "pant_f_r": 4, "pant_b_r": 4},
                pins={"pant_": 0.03})],
        body_levels=True,
    ),
    Sample(
        "layered",
        [Layer("shirt_mean", JERSEY, (0.92, 0.92, 0.88), pins=SHOULDERS, wrap=True),
         Layer("hoody_mean", FLEECE, (0.20, 0.45, 0.30), push_out=0.03, pins=SHOULDERS, wrap=True)],
        self_collision=True,
        # A 1 cm mesh and the solver's default spheres (half the mean edge: 5 mm). On the 2 cm
        # mesh the 1 cm spheres held the shirt 2 cm under the hoody and pressed its underarm
        # seams into the armpit, 1.5-5 mm open at rest; smaller spheres closed them (7 mm: 0.51
        # mm) but no longer covered the 2 cm triangles, and the shirt showed through the hoody
        # (Workbench renders at rest; sample_blends/README.md). At 1 cm: neither.
        edge=0.01,
        # Fleece on jersey grips (static 0.6, kinetic 0.4; the panel's default is 0.5 / 0.3 and
        # the solver's own for cloth on cloth 0.3 / 0.2): with 0.3 / 0.2 the hoody's shoulder
        # seams, dragged by the hood lying on the back, opened to 1.0 mm in 2 frames of 66 at
        # rest; with 0.6 / 0.4 the widest gap over those 66 frames is 0.76 mm.
        friction=(0.6, 0.4),
    ),
]
# Body regions for collision levels: the bones whose skin weights (summed) exceed 0.5.
BODY_REGIONS = {
    1: ("upper_arm.L", "forearm.L", "hand.L"),
    2: ("upper_arm.R", "forearm.R", "hand.R"),
    3: ("thigh.L", "shin.L", "foot.L", "toe.L"),
    4: ("thigh.R", "shin.R", "foot.R", "toe.R"),
}


def log(*a):
    print("garments:", *a, flush=True)


# ---- scene -----------------------------------------------------------------------------


def open_character():
    bpy.ops.wm.open_mainfile(filepath=str(SAMPLES / "character.blend"))
    rig = bpy.data.objects["Rig"]
    rig.data.pose_position = "REST"
    bpy.context.scene.frame_set(1)
    return bpy.data.objects["Body"]


def body_rest(body) -> tuple[np.ndarray, np.ndarray]:
    """World-space rest vertices and triangles of the body (its own mesh: the bind pose)."""
    me = body.data
    co = np.empty(len(me.vertices) * 3, np.float32)
    me.vertices.foreach_get("co", co)
    co = co.reshape(-1, 3)
    m = np.array(body.matrix_world, np.float32)
    co = co @ m[:3, :3].T + m[:3, 3]
    me.calc_loop_triangles()
    tris = np.empty(len(me.loop_triangles) * 3, np.int32)
    me.loop_triangles.foreach_get("vertices", tris)
    return co, tris.reshape(-1, 3)


def import_layer(layer: Layer, edge: float) -> list:
    path = PATTERNS / f"{layer.pattern}_specification.json"
    before = set(bpy.data.objects)
    assert bpy.ops.tailor.import_pattern(filepath=str(path), edge_length=edge, up_axis="Y") == {"FINISHED"}
    objs = sorted((o for o in bpy.data.objects if o not in before), key=lambda o: o.name)
    if layer.keep is not None:
        drop = [o for o in objs if o.tailor_piece.piece_name not in layer.keep]
        objs = [o for o in objs if o not in drop]
        for o in drop:
            bpy.data.objects.remove(o)
        seams = bpy.context.scene.tailor.seams
        for i in reversed(range(len(seams))):
            if seams[i].piece_a is None or seams[i].piece_b is None:
                assert bpy.ops.tailor.seam_remove(index=i) == {"FINISHED"}
    for o in objs:
        # Relative to the repository, so the committed file names no machine's paths.
        o.tailor_piece.source_path = str(path.relative_to(ROOT))
    return objs


def source_of(obj) -> str:
    return str(ROOT / obj.tailor_piece.source_path)


def to_character_frame(objs: list, push_out: float, centre: np.ndarray) -> None:
    """`push_out` metres away from the body's vertical axis along the piece's normal (an outer
    layer starts outside the inner one). The importer already turned GarmentCode's Y-up
    placements to the character's Z-up frame (its default "Y Up")."""
    for o in objs:
        if push_out:
            normal = o.matrix_world.to_3x3() @ Vector((0.0, 0.0, 1.0))
            away = Vector((o.matrix_world.translation.x - centre[0], o.matrix_world.translation.y - centre[1], 0.0))
            normal.z = 0.0
            if normal.length > 1e-6:
                normal.normalize()
                sign = 1.0 if normal.dot(away) >= 0 else -1.0
                o.location += sign * push_out * normal
    bpy.context.view_layer.update()


def piece_world(obj) -> np.ndarray:
    from tailor_addon import scene_data

    return scene_data.vertex_positions(obj)


def sewn_points(objs: list, both: bool = True) -> tuple[np.ndarray, np.ndarray]:
    """The sewn points (A side, B side) of the seams between pieces of `objs` (world, metres);
    with `both=False`, of the seams with at least one side among them."""
    from tailor_addon import scene_data

    g = scene_data.build_garment(bpy.context.scene)
    index = {o.name: i for i, o in enumerate(scene_data.piece_objects(bpy.context.scene))}
    wanted = {index[o.name] for o in objs}
    pas, pbs = [np.zeros((0, 3))], [np.zeros((0, 3))]
    for k, s in enumerate(g.seams):
        inside = (s.a.piece in wanted, s.b.piece in wanted)
        if not (all(inside) if both else any(inside)):
            continue
        av, aw, bv, bw = g.seam_pairs(k)
        pas.append(g.positions[av[:, 0]] * aw[:, :1] + g.positions[av[:, 1]] * aw[:, 1:])
        pbs.append(g.positions[bv[:, 0]] * bw[:, :1] + g.positions[bv[:, 1]] * bw[:, 1:])
    return np.concatenate(pas), np.concatenate(pbs)


def seam_gap_of(objs: list) -> float:
    """Largest distance between sewn points of the seams between pieces of `objs` (metres)."""
    pa, pb = sewn_points(objs)
    return float(np.linalg.norm(pa - pb, axis=1).max()) if len(pa) else 0.0


def seams_closing_inside(objs: list, body_v: np.ndarray, body_t: np.ndarray, both: bool = True) -> int:
    """How many sewn pairs would close through the body: a closing seam draws its two points
    together along the line between them, so a pair whose line passes through the body (11
    points on it tested) is a seam cutting through it (the paper's reason for bending sleeves,
    Sec. 4); cloth kept outside then slides round the body instead, or under a shoulder."""
    pa, pb = sewn_points(objs, both)
    if not len(pa):
        return 0
    t = np.linspace(0.0, 1.0, 11)[:, None, None]
    line = (1.0 - t) * pa[None] + t * pb[None]  # (11, pairs, 3)
    hit = (signed_distance(line.reshape(-1, 3), body_v, body_t) < 0.0).reshape(len(t), -1).any(axis=0)
    return int(hit.sum())


def signed_distance(points: np.ndarray, body_v: np.ndarray, body_t: np.ndarray) -> np.ndarray:
    """Distance of each point from its nearest body vertex, negative behind that vertex's
    normal (inside): a quick test for the placement search on the dense (1 cm) body mesh."""
    v = np.asarray(body_v, np.float64)
    t = np.asarray(body_t, np.int64)
    fn = np.cross(v[t[:, 1]] - v[t[:, 0]], v[t[:, 2]] - v[t[:, 0]])
    n = np.zeros_like(v)
    for k in range(3):
        np.add.at(n, t[:, k], fn)
    n /= np.maximum(np.linalg.norm(n, axis=1, keepdims=True), 1e-12)
    out = np.empty(len(points))
    for i in range(0, len(points), 256):
        c = np.asarray(points[i:i + 256], np.float64)
        j = ((c[:, None, :] - v[None]) ** 2).sum(-1).argmin(axis=1)
        d = c - v[j]
        out[i:i + 256] = np.sign((d * n[j]).sum(1)) * np.linalg.norm(d, axis=1)
    return out


def piece_strain(obj) -> float:
    """Largest edge strain of a piece's placed (bent) shape against its rest shape: a bend is
    not an isometry, and a stretched start snaps back when the simulation starts."""
    from tailor_addon import scene_data

    rest = scene_data.rest_of(obj).astype(np.float64)
    x = piece_world(obj).astype(np.float64)
    ev = np.empty(len(obj.data.edges) * 2, np.int32)
    obj.data.edges.foreach_get("vertices", ev)
    e = ev.reshape(-1, 2)
    l0 = np.linalg.norm(rest[e[:, 0]] - rest[e[:, 1]], axis=1)
    l1 = np.linalg.norm(x[e[:, 0]] - x[e[:, 1]], axis=1)
    return float(np.abs(l1 / np.maximum(l0, 1e-12) - 1.0).max())


def lift_clear_of_body(objs: list, body_v: np.ndarray, body_t: np.ndarray) -> dict:
    """Raises a layer by the smallest of LIFTS that puts no seam's closing point inside the
    body (the limb seams aside: bending handles those). GarmentCode places the shirt's
    shoulder seams 3-6 cm below the mean body's shoulder line, so they close through the
    shoulders, or, with the solver keeping cloth on the side it came from, under them, and the
    shirt falls off. Gravity is held while seams close, then drops the garment onto the body."""
    limb = [o for o in objs if any(k in o.tailor_piece.piece_name for pair in LIMB_PAIRS for k in pair)]
    torso = [o for o in objs if o not in limb]
    tried = []
    for lift in LIFTS:
        for o in objs:
            o.location.z += lift - (tried[-1][0] if tried else 0.0)
        bpy.context.view_layer.update()
        inside = seams_closing_inside(torso, body_v, body_t, both=False) if torso else 0
        tried.append((lift, inside))
        if inside == 0:
            break
    best = min(tried, key=lambda r: (r[1], r[0]))
    for o in objs:
        o.location.z += best[0] - tried[-1][0]
    bpy.context.view_layer.update()
    log(f"  lift: {', '.join(f'{a * 100:g} cm: {c} seam points close inside' for a, c in tried)} -> {best[0] * 100:g} cm")
    return {"lift_m": best[0], "tried": [{"lift_m": a, "inside": c} for a, c in tried]}


def wrap_torso(objs: list, body_v: np.ndarray, body_t: np.ndarray) -> dict:
    """Lifts a layer and wraps its torso panels round the body's sides, the lift (WRAP_LIFTS)
    and the angle (WRAP_ANGLES) searched together. A flat front panel is wider than the chest:
    its side edge stands in front of the upper arm, and the side seam's top pairs close through
    the arm. The sleeveless hoody's did (2 of 15 pairs per side seam, 5 cm from the arm's inner
    surface at 1.24 m): its panels closed over the arms, edges stretched 4x, and on the left
    the shirt ended up outside the hoody. Each panel is bent about a vertical axis through its
    centre-front (or centre-back) edge, the bend growing towards the side edge, which comes
    round towards the partner panel, so the side seam closes in the gap under the arm. The
    inner layer is wrapped too: a wrapped outer layer next to a flat inner one starts with its
    sides inside the inner layer's wider flat panels (measured: the hoody then assembled under
    the shirt's sides). The pick: no vertex inside the body and at most MAX_WRAP_STRAIN start
    stretch, then the fewest seam points of the layer closing inside the body, the smallest
    angle, the smallest lift."""
    by_name = {o.tailor_piece.piece_name: o for o in objs}
    pairs = [(by_name[f], by_name[b]) for f, b in TORSO_PAIRS if f in by_name and b in by_name]
    setups = [(wrap_setup(f, b), wrap_setup(b, f)) for f, b in pairs]
    tried, at = [], 0.0
    for lift in WRAP_LIFTS:
        for o in objs:
            o.location.z += lift - at
        at = lift
        bpy.context.view_layer.update()
        for angle in WRAP_ANGLES:
            for pair, setup in zip(pairs, setups):
                for o, st in zip(pair, setup):
                    apply_bend(o, st, angle)
            pen = tailor.penetration(np.concatenate([piece_world(o) for o in objs]), body_v, body_t)
            strain = max(piece_strain(o) for pair in pairs for o in pair)
            tried.append((lift, angle, seams_closing_inside(objs, body_v, body_t, both=False), int(pen["count"]), strain))
    ok = [r for r in tried if r[3] == 0 and r[4] <= MAX_WRAP_STRAIN] or tried[:1]
    best = min(ok, key=lambda r: (r[2], r[1], r[0]))
    for o in objs:
        o.location.z += best[0] - at
    bpy.context.view_layer.update()
    for pair, setup in zip(pairs, setups):
        for o, st in zip(pair, setup):
            apply_bend(o, st, best[1])
    log(f"  wrap: {len(tried)} (lift, angle) tried; {sum(r[2] == 0 for r in ok)} with no seam point closing "
        f"inside -> lift {best[0] * 100:g} cm, {best[1]:g} deg ({best[2]} closing inside, strain {best[4]:.2f})")
    return {"lift_m": best[0], "wrap_deg": best[1],
            "tried": [{"lift_m": a, "angle_deg": b, "inside": c, "vertices_inside": d, "strain": e}
                      for a, b, c, d, e in tried]}


def wrap_setup(obj, partner) -> dict:
    """The wrap of torso panel `obj` (see `wrap_torso`) in its local frame: the symmetry line
    and the axis run upright through the vertex nearest the body's midline (x = 0: the
    character is centred), so the bend is 0 there and grows towards the side edge; `depth`
    (1 mm towards `partner`) gives `apply_bend` the sense."""
    from tailor_addon import scene_data

    rest = scene_data.rest_of(obj).astype(np.float64)
    q = rest[np.argmin(np.abs(piece_world(obj)[:, 0]))]
    up = obj.matrix_world.to_3x3().inverted() @ Vector((0.0, 0.0, 1.0))
    e = np.array([up.x, up.y]) / math.hypot(up.x, up.y)
    towards = (obj.matrix_world.inverted() @ partner.matrix_world.translation).z
    return {"c": q, "e": e, "depth": math.copysign(1e-3, towards)}


def bend_limbs(objs: list, body_v: np.ndarray, body_t: np.ndarray) -> list[dict]:
    """Bends each front/back limb panel pair around the limb between them (see the module doc)."""
    out = []
    by_name = {o.tailor_piece.piece_name: o for o in objs}
    for front_key, back_key in LIMB_PAIRS:
        for name, obj in by_name.items():
            if front_key not in name:
                continue
            partner = by_name.get(name.replace(front_key, back_key))
            if partner is None:
                continue
            pair = [obj, partner]
            setups = [limb_bend_setup(o, p) for o, p in ((obj, partner), (partner, obj))]
            results = []
            for angle in BEND_ANGLES:
                for o, setup in zip(pair, setups):
                    apply_bend(o, setup, angle)
                gap = seam_gap_of(pair)
                pts = np.concatenate([piece_world(o) for o in pair])
                pen = tailor.penetration(pts, body_v, body_t)
                strain = max(piece_strain(o) for o in pair)
                results.append((angle, gap, int(pen["count"]), seams_closing_inside(pair, body_v, body_t), strain))
            # No vertex inside, a strain the start can take; then the fewest seam points closing
            # inside the limb, then the smallest gap.
            ok = [r for r in results if r[2] == 0 and r[4] <= MAX_BEND_STRAIN] or results[:1]
            best = min(ok, key=lambda r: (r[3], r[1]))
            for o, setup in zip(pair, setups):
                apply_bend(o, setup, best[0])
            figures = ", ".join(f"{a:g} deg: gap {g * 100:.1f} cm, {c} inside, {m} closing inside, strain {st:.2f}"
                                for a, g, c, m, st in results)
            log(f"  bend {obj.name}+{partner.name}: {figures} -> {best[0]:g} deg")
            out.append({"pieces": [obj.name, partner.name], "angle_deg": best[0],
                        "tried": [{"angle_deg": a, "seam_gap_m": g, "inside": c, "closing_inside": m, "strain": st}
                                  for a, g, c, m, st in results]})
    return out


def limb_bend_setup(obj, partner) -> dict:
    """The bend of `obj` around the limb between it and `partner`, in `obj`'s local frame: the
    axis runs along the piece's long (principal) direction, halfway to the partner panel; the
    symmetry line is the piece's centre line; `sign` turns the edges towards the partner."""
    from tailor_addon import scene_data

    rest = scene_data.rest_of(obj).astype(np.float64)
    c = rest.mean(axis=0)
    w, v = np.linalg.eigh(np.cov((rest - c).T))
    e = v[:, np.argmax(w)]
    mid = (obj.matrix_world.inverted() @ partner.matrix_world.translation)
    depth = mid.z / 2.0
    return {"c": c, "e": e, "depth": depth}


def apply_bend(obj, setup: dict, angle_deg: float) -> None:
    c, e, depth = setup["c"], setup["e"], setup["depth"]
    ctx = bpy.context
    for o in ctx.view_layer.objects:
        o.select_set(False)
    obj.select_set(True)
    ctx.view_layer.objects.active = obj
    # Positive angles about +e turn the far vertices of both halves towards local +z or -z
    # depending on e's sense: pick the sense that moves them towards the partner (depth's sign).
    angle = math.radians(angle_deg)
    kw = dict(axis_point=(float(c[0]), float(c[1]), float(depth)), axis_direction=(float(e[0]), float(e[1]), 0.0),
              use_symmetry=True, symmetry_point=(float(c[0]), float(c[1])),
              symmetry_direction=(float(e[0]), float(e[1])), threshold=0.0)
    assert bpy.ops.tailor.bend(angle=angle, **kw) == {"FINISHED"}
    if angle_deg:
        z = np.empty(len(obj.data.vertices) * 3, np.float32)
        obj.data.vertices.foreach_get("co", z)
        if np.sign(z.reshape(-1, 3)[:, 2].mean()) != np.sign(depth):
            assert bpy.ops.tailor.bend(angle=-angle, **kw) == {"FINISHED"}


def paint_levels(objs: list, layer: Layer) -> None:
    ctx = bpy.context
    for o in objs:
        level = next((lv for prefix, lv in layer.levels.items() if o.tailor_piece.piece_name.startswith(prefix)), 0)
        if not level:
            continue
        ctx.view_layer.objects.active = o
        assert bpy.ops.tailor.collision_level_set(level=level, only_selected=False) == {"FINISHED"}


def select_vertices(obj, sel: np.ndarray) -> None:
    """Selects exactly `sel` (vertices, and the edges and faces all of whose vertices are in
    it, so Edit Mode keeps the selection as it is)."""
    me = obj.data
    me.vertices.foreach_set("select", sel)
    ev = np.empty(len(me.edges) * 2, np.int32)
    me.edges.foreach_get("vertices", ev)
    me.edges.foreach_set("select", sel[ev.reshape(-1, 2)].all(axis=1))
    lv = np.empty(len(me.loops), np.int32)
    me.loops.foreach_get("vertex_index", lv)
    start = np.empty(len(me.polygons), np.int32)
    me.polygons.foreach_get("loop_start", start)
    me.polygons.foreach_set("select", np.logical_and.reduceat(sel[lv], start) if len(start) else np.zeros(0, bool))


def paint_pins(objs: list, layer: Layer) -> None:
    """Pin weight 1 on the top `band` metres of the pieces named in `layer.pins` (in Edit Mode,
    through the add-on's paint operator): the demo attaches these particles to the body."""
    from tailor_addon import scene_data

    ctx = bpy.context
    for o in objs:
        band = next((b for prefix, b in layer.pins.items() if o.tailor_piece.piece_name.startswith(prefix)), None)
        if band is None:
            continue
        rest = scene_data.rest_of(o)
        sel = rest[:, 1] >= rest[:, 1].max() - band
        for other in ctx.view_layer.objects:
            other.select_set(False)
        o.select_set(True)
        ctx.view_layer.objects.active = o
        select_vertices(o, sel)
        bpy.ops.object.mode_set(mode="EDIT")
        assert bpy.ops.tailor.paint_set(map="PIN", value=1.0, only_selected=True) == {"FINISHED"}
        bpy.ops.object.mode_set(mode="OBJECT")
        select_vertices(o, np.zeros(len(sel), bool))


def paint_body_levels(body) -> dict[int, int]:
    """Arms 1/2, legs 3/4 on the body, selected from the skin weights and set in Edit Mode."""
    ctx = bpy.context
    n = len(body.data.vertices)
    groups = {g.name: g.index for g in body.vertex_groups}
    weight = np.zeros((len(groups), n), np.float32)
    for v in body.data.vertices:
        for g in v.groups:
            weight[g.group, v.index] = g.weight
    counts = {}
    for o in ctx.view_layer.objects:
        o.select_set(False)
    body.select_set(True)
    ctx.view_layer.objects.active = body
    for level, bones in BODY_REGIONS.items():
        sel = weight[[groups[b] for b in bones]].sum(axis=0) > 0.5
        select_vertices(body, sel)
        bpy.ops.object.mode_set(mode="EDIT")
        assert bpy.ops.tailor.collision_level_set(level=level, only_selected=True) == {"FINISHED"}
        bpy.ops.object.mode_set(mode="OBJECT")
        counts[level] = int(sel.sum())
    select_vertices(body, np.zeros(n, bool))
    return counts


def set_fabric(objs: list, layer: Layer) -> None:
    for o in objs:
        p = o.tailor_piece
        for k, v in layer.fabric.items():
            setattr(p, k, v)
        mat = bpy.data.materials.get(f"Cloth {layer.pattern}") or bpy.data.materials.new(f"Cloth {layer.pattern}")
        mat.diffuse_color = (*layer.colour, 1.0)
        o.data.materials.clear()
        o.data.materials.append(mat)


# ---- garment file ------------------------------------------------------------------------


def piece_entry(obj, template: dict) -> dict:
    """One manifest piece from a piece object: source and options as the importer saves them,
    the placement from the object's transform turned to Y-up, the stored bend likewise."""
    p = obj.tailor_piece
    m = Z_TO_Y @ obj.matrix_world
    loc, rot = m.to_translation(), m.to_euler("ZYX")
    entry = dict(template)
    entry["placement"] = {"translation": [float(x) for x in loc], "rotation_deg": [math.degrees(a) for a in rot]}
    entry["bend"] = None
    if p.bend_angle:
        m3 = m.to_3x3()
        point = m @ Vector(p.bend_axis_point)
        direction = m3 @ Vector(p.bend_axis_direction)
        entry["bend"] = {
            "axis_point": list(point),
            "axis_direction": list(direction),
            "angle_deg": math.degrees(p.bend_angle),
            "symmetry": {"point": list(p.bend_symmetry_point), "direction": list(p.bend_symmetry_direction)}
            if p.bend_symmetry else None,
            "threshold": p.bend_threshold,
        }
    return entry


def export_garment(sample: Sample, path: Path, body) -> None:
    """Writes the scene's garment as a garment file and checks that it rebuilds the scene."""
    from tailor_addon import scene_data
    from tailor_addon.core.paint import LEVEL_ATTR
    from tailor_addon.paint.maps import painted_maps

    scene = bpy.context.scene
    objs = scene_data.piece_objects(scene)
    # Templates: each source pattern saved by the module, so `source` and `options` are the
    # module's own serialisation of exactly the pieces the importer made.
    templates = {}
    with tempfile.TemporaryDirectory() as tmp:
        for src in sorted({source_of(o) for o in objs}):
            edge = next(o.tailor_piece.edge_length for o in objs if source_of(o) == src)
            g = tailor.Garment.from_pattern(src, edge=edge)
            g.save(str(Path(tmp) / "t.json"))
            templates[src] = json.loads((Path(tmp) / "t.json").read_text())
    index = {o.name: i for i, o in enumerate(objs)}
    pieces = [piece_entry(o, templates[source_of(o)]["pieces"][o.tailor_piece.source_index]) for o in objs]
    seams = [seam_serde(scene_data.read_seam(item, index)) for item in scene.tailor.seams]
    head = next(iter(templates.values()))
    head["pieces"], head["seams"], head["particle_params"] = pieces, seams, []
    head["settings"] = {"pattern_sources": [str(Path(p).resolve().relative_to(ROOT)) for p in sorted(templates)],
                        "tailor_sample": {"character": "character.glb", "up": "y"}}
    tmp_manifest = path.with_suffix(".json")
    bin_path = path.with_suffix(".bin")
    if bin_path.exists():
        bin_path.unlink()
    tmp_manifest.write_text(json.dumps({**head, "particle_params": [], "sidecar": {"file": bin_path.name}}, indent=2))
    # The pieces and seams as written above, then the setup and painted maps exactly as the
    # add-on's export gives them (`core.simulate.garment_of`), saved by the module.
    from tailor_addon.core import simulate as core_sim
    from tailor_addon.simulate import gather

    chosen = core_sim.SimSettings(thickness=sample.thickness, self_collision=sample.self_collision,
                                  self_collision_radius=sample.self_collision_radius,
                                  friction_static=sample.friction[0], friction_kinetic=sample.friction[1])
    g = load_unsigned(tmp_manifest)
    core_sim.garment_of(g, sample.name, chosen, gather.fabrics(objs), [painted_maps(o) for o in objs],
                        scene_data.point_attribute(body.data, LEVEL_ATTR, np.int32))
    g.save(str(tmp_manifest))
    check_export(tmp_manifest, objs)


def load_unsigned(manifest: Path) -> "tailor.Garment":
    """A manifest written by hand with no painted maps, read by the module: an empty sidecar
    (its magic bytes) is written beside it and signed in the manifest first."""
    head = json.loads(manifest.read_text())
    bin_path = manifest.with_suffix(".bin")
    magic = b"TLRBIN\x00\x01"
    bin_path.write_bytes(magic)
    h = 0xCBF29CE484222325
    for b in magic:
        h = ((h ^ b) * 0x100000001B3) & 0xFFFFFFFFFFFFFFFF
    head["sidecar"] = {"file": bin_path.name, "bytes": len(magic), "fnv1a64": f"{h:016x}"}
    manifest.write_text(json.dumps(head, indent=2))
    return tailor.Garment.load(str(manifest))


def seam_serde(s: SeamData) -> dict:
    """A stored seam in the manifest's form (serde: `Ccw`/`Cw`, `Equal`/`Unequal`)."""
    side = lambda x: {"piece": x.piece, "start": list(x.start), "end": list(x.end),  # noqa: E731
                      "direction": x.direction.capitalize()}
    return {"name": s.name, "a": side(s.a), "b": side(s.b), "mode": s.mode.capitalize(),
            "stiffness": s.stiffness, "bend_stiffness": s.bend_stiffness}


def check_export(manifest: Path, objs: list) -> None:
    g = tailor.Garment.load(str(manifest))
    sim, offsets = g.build_simulation()
    want = np.concatenate([piece_world(o) for o in objs]) @ np.array(Z_TO_Y.to_3x3(), np.float32).T
    err = float(np.abs(sim.positions - want).max())
    log(f"  {manifest.name}: {len(g.pieces)} pieces, {len(g.seams)} seams, {sim.num_particles} particles; "
        f"rebuilt positions within {err * 1e3:.4f} mm of the scene")
    if err > 1e-5:
        raise SystemExit(f"{manifest}: the garment file does not rebuild the scene ({err * 1e3:.3f} mm)")


# ---- main --------------------------------------------------------------------------------


def build(sample: Sample, edge: float) -> dict:
    log(f"{sample.name}:")
    body = open_character()
    body_v, body_t = body_rest(body)
    centre = body_v[:, :2].mean(axis=0)
    info = {"name": sample.name, "layers": []}
    for layer in sample.layers:
        objs = import_layer(layer, edge)
        to_character_frame(objs, layer.push_out, centre)
        lift = wrap_torso(objs, body_v, body_t) if layer.wrap else lift_clear_of_body(objs, body_v, body_t)
        bends = bend_limbs(objs, body_v, body_t)
        paint_levels(objs, layer)
        paint_pins(objs, layer)
        set_fabric(objs, layer)
        info["layers"].append({"pattern": layer.pattern, "pieces": [o.name for o in objs], "lift": lift,
                               "bends": bends})
    if sample.body_levels:
        info["body_levels"] = paint_body_levels(body)
        log(f"  body collision levels: {info['body_levels']} vertices")
    scene = bpy.context.scene
    info["seams"] = len(scene.tailor.seams)
    scene.tailor.show_seams = True
    # The simulation settings the garment file records, so that Live and Bake in the .blend
    # simulate the sample as the checks and tests do.
    s = scene.tailor_simulate
    s.thickness = sample.thickness
    s.self_collision = sample.self_collision
    s.self_collision_radius = sample.self_collision_radius
    s.friction_static, s.friction_kinetic = sample.friction
    out = SAMPLES / f"{sample.name}.blend"
    bpy.ops.wm.save_as_mainfile(filepath=str(out), compress=True, relative_remap=True)
    export_garment(sample, SAMPLES / f"{sample.name}.json", body)
    log(f"  wrote {out.name}, {sample.name}.json/.bin ({info['seams']} seams)")
    return info


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--only", help="comma-separated sample names")
    ap.add_argument("--edge", type=float, help="piece resolution, metres (default: each sample's own)")
    args = ap.parse_args(argv)
    import tailor_addon

    bpy.context.preferences.filepaths.save_version = 0  # no .blend1 backups beside the samples
    tailor_addon.register()
    try:
        wanted = set(args.only.split(",")) if args.only else None
        for sample in SAMPLES_SPEC:
            if wanted is None or sample.name in wanted:
                build(sample, args.edge or sample.edge)
    finally:
        tailor_addon.unregister()  # bpy 4.5 hangs at exit while operator classes are registered
    return 0


if __name__ == "__main__":
    sys.exit(main())
