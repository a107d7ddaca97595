"""The peer benchmark's scenes, built once by Tailor and exported as plain arrays.

Every peer (Tailor, Blender's Cloth, Newton) runs the *same* exported geometry: the same
particles in the same order, the same triangles, the same sewn pairs, the same pins, the same
body, the same gravity, frame rate and number of frames. A scene is a dict of numpy arrays and
scalars, saved as one ``.npz`` so that each peer can load it in its own process.

Scenes:

* ``sheet-1k`` / ``sheet-10k``: a 1 m square sheet (32² and 100² particles) starting
  horizontal, its top edge pinned, swinging down under gravity (Z up). No body, no seams.
* ``shirt-1k`` / ``shirt-5k`` / ``shirt-10k``: the GarmentCode shirt
  (``shirt_mean_specification.json``) triangulated at 30 mm, 12 mm (issue 22's 1.2 cm, 5,485
  particles) and 8.8 mm, placed around the GarmentCode mean body (Y up, static),
  its seams closing from up to 43 cm apart: the *assembly*, with gravity off. (With gravity on
  from the first frame, as ``tailor simulate`` runs it, the open pieces slide down the body while
  the seams close and the shirt ends below the feet, in Tailor as well; the quality metrics of
  a shirt on the floor say nothing.) Needs the shared body mesh; skipped without it.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

import tailor

REPO = Path(__file__).resolve().parents[2]
SHIRT = REPO / "native/tailor-core/tests/data/garmentcode/shirt_mean_specification.json"
# The GarmentCode mean body, as copied into the repository with its licence
# (sample_blends/sources/LICENSE-mean_all.txt; the same file as ../shared/data's).
BODY = REPO / "sample_blends/sources/mean_all.obj"

FABRIC = dict(density=0.15, stretch=600.0, shear=60.0, bend=2e-5)  # Tailor's defaults, SI units
FPS = 30.0
THICKNESS = 0.004  # m, as `tailor simulate`

SCENES = {
    "sheet-1k": dict(kind="sheet", n=32, frames=45),
    "sheet-10k": dict(kind="sheet", n=100, frames=45),
    "shirt-1k": dict(kind="shirt", edge=0.03, frames=45),
    "shirt-5k": dict(kind="shirt", edge=0.012, frames=45),  # issue 22's shirt at 1.2 cm
    "shirt-10k": dict(kind="shirt", edge=0.0088, frames=45),
}


def available(name: str) -> str | None:
    """None when the scene can be built here, else why not."""
    if SCENES[name]["kind"] == "shirt" and not BODY.exists():
        return f"body mesh {BODY} absent"
    return None


def _grid(n: int, size: float = 1.0):
    """n x n particles over a size x size square; two triangles per cell."""
    u = np.linspace(0.0, size, n, dtype=np.float32)
    uu, vv = np.meshgrid(u, u, indexing="ij")  # uu: along the pinned edge, vv: away from it
    rest = np.stack([uu.ravel(), vv.ravel()], 1)
    idx = np.arange(n * n).reshape(n, n)
    a, b, c, d = idx[:-1, :-1].ravel(), idx[1:, :-1].ravel(), idx[1:, 1:].ravel(), idx[:-1, 1:].ravel()
    tris = np.concatenate([np.stack([a, b, c], 1), np.stack([a, c, d], 1)]).astype(np.uint32)
    return rest, tris, idx[:, 0]


def build_simulation(scene: dict, substeps: int, iterations: int):
    """Tailor's own simulation of an exported scene (so Tailor also runs the exported arrays)."""
    settings = tailor.Settings(substeps=substeps, iterations=iterations, gravity=tuple(scene["gravity"]))
    fabric = tailor.Fabric(**{k: float(scene[k]) for k in FABRIC})
    sim = tailor.Simulation(scene["positions"], scene["triangles"], scene["rest"], fabric, settings)
    if len(scene["pinned"]):
        sim.pin(scene["pinned"])
    off = scene["seam_offsets"]
    for k in range(len(off) - 1):
        s = slice(off[k], off[k + 1])
        sim.add_weighted_seam(scene["seam_a_vertices"][s], scene["seam_a_weights"][s], scene["seam_b_vertices"][s],
                              scene["seam_b_weights"][s], stiffness=float(scene["seam_stiffness"][k]),
                              bend_stiffness=float(scene["seam_bend_stiffness"][k]), name=f"seam{k}")
    sim.thickness = float(scene["thickness"])
    radius = float(scene["self_collision_radius"]) if "self_collision_radius" in scene else 0.0
    sim.set_self_collision(enabled=bool(scene["self_collision"]), radius=radius if radius > 0 else None)
    cid = None
    if len(scene["body_triangles"]):
        cid = sim.add_mesh_collider(scene["body_vertices"], scene["body_triangles"])
    return sim, cid


def build(name: str) -> dict:
    """The exported arrays of scene `name`."""
    spec = SCENES[name]
    why = available(name)
    if why:
        raise FileNotFoundError(why)
    if spec["kind"] == "sheet":
        rest, tris, pinned = _grid(spec["n"])
        pos = np.stack([rest[:, 0], rest[:, 1], np.full(len(rest), 1.2, np.float32)], 1)  # horizontal, 1.2 m up
        sim = tailor.Simulation(pos, tris, rest, tailor.Fabric(**FABRIC))
        body_v, body_t = np.zeros((0, 3), np.float32), np.zeros((0, 3), np.uint32)
        gravity = (0.0, 0.0, -9.81)
    else:
        garment = tailor.Garment.from_pattern(str(SHIRT), edge=spec["edge"])
        sim, _ = garment.build_simulation(fabric=tailor.Fabric(**FABRIC))
        pinned = np.zeros(0, np.int64)
        body_v, body_t = tailor.read_mesh(BODY)
        gravity = (0.0, 0.0, 0.0)  # assembly (see the module doc); the body is Y up
    return export(name, sim, pinned, body_v, body_t, gravity, spec["frames"])


def export(name: str, sim, pinned, body_v, body_t, gravity, frames: int) -> dict:
    """The arrays every peer runs: Tailor's `sim` as built (particles, triangles, rest shape,
    masses, sewn pairs), its pins, the body, gravity and the number of frames."""
    seams = sim.seam_pairs()
    empty2 = np.zeros((0, 2), np.uint32)
    cat = lambda key, empty: np.concatenate([s[key] for s in seams]) if seams else empty  # noqa: E731
    edges = sim.edges
    rest = sim.rest
    rest_len = np.linalg.norm(rest[edges[:, 0]] - rest[edges[:, 1]], axis=1).astype(np.float32)
    return dict(
        name=name,
        positions=sim.positions,
        triangles=sim.triangles,
        rest=rest,
        edges=edges,
        rest_lengths=rest_len,
        masses=sim.masses,
        pinned=np.asarray(pinned, np.uint32),
        seam_a_vertices=cat("a_vertices", empty2),
        seam_a_weights=cat("a_weights", np.zeros((0, 2), np.float32)),
        seam_b_vertices=cat("b_vertices", empty2),
        seam_b_weights=cat("b_weights", np.zeros((0, 2), np.float32)),
        seam_offsets=np.cumsum([0] + [len(s["a_vertices"]) for s in seams]).astype(np.int64),
        seam_stiffness=np.array([s["stiffness"] for s in seams], np.float32),
        seam_bend_stiffness=np.array([s["bend_stiffness"] for s in seams], np.float32),
        body_vertices=np.asarray(body_v, np.float32).reshape(-1, 3),
        body_triangles=np.asarray(body_t, np.uint32).reshape(-1, 3),
        gravity=np.array(gravity, np.float32),
        fps=np.float32(FPS),
        frames=np.int64(frames),
        thickness=np.float32(THICKNESS),
        self_collision=np.bool_(False),
        closing_speed=np.float32(tailor.Settings().ramp_closing_speed),
        **{k: np.float32(v) for k, v in FABRIC.items()},
    )


def vertex_pairs(scene: dict) -> np.ndarray:
    """The sewn pairs rounded to vertex-vertex pairs (k, 2), for peers whose seams join vertices
    only (Blender's sewing springs, Newton's springs): each side's point becomes its heavier
    vertex; pairs that collapse onto one vertex and repeated pairs are dropped."""
    if not len(scene["seam_a_vertices"]):
        return np.zeros((0, 2), np.int64)

    def heavier(v, w):
        return np.where(w[:, 0] >= w[:, 1], v[:, 0], v[:, 1]).astype(np.int64)

    a = heavier(scene["seam_a_vertices"], scene["seam_a_weights"])
    b = heavier(scene["seam_b_vertices"], scene["seam_b_weights"])
    p = np.sort(np.stack([a, b], 1), 1)
    p = p[p[:, 0] != p[:, 1]]
    return np.unique(p, axis=0)


def save(scene: dict, path: Path) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    np.savez(path, **scene)


def load(path: Path) -> dict:
    with np.load(path, allow_pickle=False) as z:
        return {k: (z[k].item() if z[k].ndim == 0 else z[k]) for k in z.files}
