"""Newton's cloth solvers (``pip install newton``; NVIDIA Warp kernels on the CPU device).

Knobs: ``solver`` (``xpbd`` or ``style3d``), ``substeps`` per frame, ``iterations`` per substep.

* XPBD: one distance constraint per mesh edge at its flat rest length with compliance
  ``1/k``, ``k = sqrt(3)/2 * stretch`` (the spring constant of an isotropic triangle net with
  Tailor's 2D stretch modulus), Newton's dihedral bending per interior edge with Tailor's bend
  and a flat rest angle, and one zero-length spring per sewn vertex pair with Tailor's seam
  stiffness, its rest length shrinking at Tailor's closing speed (the same schedule as Tailor's
  seam ramp). The body is a static mesh shape; contacts use the particle radius = thickness.
  Particle-particle contacts are off (``particle_max_radius = 0``), as Tailor's self-collision.
* Style3D: Newton's projective-dynamics cloth with Tailor's anisotropic stretch
  ``(stretch, stretch, shear)`` and bend on the flat 2D rest shape. It has no springs or seam
  constraints (its solver reads none), so it runs only scenes without seams.

Masses are the scene's (Tailor's, from rest areas); pinned particles get zero inverse mass.
"""

from __future__ import annotations

import math
import time

import numpy as np

import scenes


def _common(scene):
    import newton

    up = newton.Axis.Y if len(scene["body_triangles"]) else newton.Axis.Z  # the body mesh is Y up
    return newton.ModelBuilder(up_axis=up, gravity=tuple(float(g) for g in scene["gravity"]))


def has_seams(scene: dict) -> bool:
    return bool(len(scene["seam_a_vertices"]))


def run(scene: dict, knob: dict, cap: float = float("inf")) -> dict:
    import warp as wp

    wp.config.quiet = True
    import newton
    from newton.solvers import style3d

    t0 = time.perf_counter()
    wp.init()
    device = wp.get_device("cpu")
    pos, tris, rest = scene["positions"], scene["triangles"], scene["rest"]
    n = len(pos)
    th = float(scene["thickness"])
    solver_name = knob["solver"]
    builder = _common(scene)
    pairs = scenes.vertex_pairs(scene)
    zero3, ident = wp.vec3(0.0, 0.0, 0.0), wp.quat_identity()
    if solver_name == "xpbd":
        builder.add_cloth_mesh(pos=zero3, rot=ident, scale=1.0, vel=zero3, vertices=pos.tolist(),
                               indices=tris.ravel().tolist(), density=float(scene["density"]),
                               edge_ke=float(scene["bend"]), edge_kd=0.0, add_springs=False, particle_radius=th)
        k_edge = math.sqrt(3.0) / 2.0 * float(scene["stretch"])
        for a, b in scene["edges"]:
            builder.add_spring(int(a), int(b), k_edge, 0.0, control=0.0)
        n_edge_springs = len(scene["edges"])
        seam_k = float(np.max(scene["seam_stiffness"])) if has_seams(scene) else 0.0
        for a, b in pairs:
            builder.add_spring(int(a), int(b), seam_k, 0.0, control=0.0)
    elif solver_name == "style3d":
        if has_seams(scene):
            raise NotImplementedError("newton's SolverStyle3D has no spring or seam constraints")
        newton.solvers.SolverStyle3D.register_custom_attributes(builder)
        s, sh, bd = float(scene["stretch"]), float(scene["shear"]), float(scene["bend"])
        style3d.add_cloth_mesh(builder, pos=zero3, rot=ident, vel=zero3, vertices=pos.tolist(),
                               indices=tris.ravel().tolist(), panel_verts=rest.tolist(),
                               panel_indices=tris.ravel().tolist(), density=float(scene["density"]), scale=1.0,
                               particle_radius=th, tri_aniso_ke=wp.vec3(s, s, sh), edge_aniso_ke=wp.vec3(bd, bd, bd))
    else:
        raise ValueError(f"unknown Newton solver {solver_name!r}")
    masses = scene["masses"].astype(float).copy()
    masses[scene["pinned"].astype(np.int64)] = 0.0
    for i in range(n):
        builder.particle_mass[i] = float(masses[i])
    if len(scene["body_triangles"]):
        body = newton.Mesh(scene["body_vertices"], scene["body_triangles"].ravel())
        builder.add_shape_mesh(body=-1, mesh=body)
    model = builder.finalize(device=device)
    if len(scene["pinned"]):
        flags = model.particle_flags.numpy()
        flags[scene["pinned"].astype(np.int64)] &= ~int(newton.ParticleFlags.ACTIVE)
        model.particle_flags.assign(flags)
    # No particle-particle (self) contacts, as in Tailor's scenes.
    model.particle_max_radius = 0.0
    model.particle_grid = None
    seam_rest0 = None
    if solver_name == "xpbd":
        rl = model.spring_rest_length.numpy()
        rl[:n_edge_springs] = scene["rest_lengths"]
        seam_rest0 = rl[n_edge_springs:].copy()
        model.spring_rest_length.assign(rl)
        model.edge_rest_angle.assign(np.zeros(model.edge_count, np.float32))
        solver = newton.solvers.SolverXPBD(model, iterations=int(knob["iterations"]))
    else:
        solver = newton.solvers.SolverStyle3D(
            model=model, config=newton.solvers.SolverStyle3D.Config(iterations=int(knob["iterations"])))
    state0, state1, control = model.state(), model.state(), model.control()
    pipeline = newton.CollisionPipeline(model, soft_contact_margin=2.0 * th)
    contacts = pipeline.contacts()
    setup = time.perf_counter() - t0

    fps, substeps = float(scene["fps"]), int(knob["substeps"])
    dt = 1.0 / fps / substeps
    speed = float(scene["closing_speed"])
    wall, cpu, nan_frame = [], [], None
    for f in range(int(scene["frames"])):
        if sum(wall[1:]) > cap:  # the first frame (Warp compiles its kernels there) does not count
            break
        w0, c0 = time.perf_counter(), time.process_time()
        if seam_rest0 is not None and len(seam_rest0):
            rl = model.spring_rest_length.numpy()
            rl[n_edge_springs:] = np.maximum(seam_rest0 - speed * (f + 1) / fps, 0.0)
            model.spring_rest_length.assign(rl)
        for _ in range(substeps):
            state0.clear_forces()
            if pipeline:
                pipeline.collide(state0, contacts)
            solver.step(state0, state1, control, contacts, dt)
            state0, state1 = state1, state0
        x = state0.particle_q.numpy()  # synchronises the device: the frame is done
        wall.append(time.perf_counter() - w0)
        cpu.append(time.process_time() - c0)
        if nan_frame is None and not np.isfinite(x).all():
            nan_frame = f + 1
    return dict(frame_wall_s=wall, frame_cpu_s=cpu, setup_s=setup, final=np.asarray(x, np.float32), nan_frame=nan_frame,
                version=f"newton {newton.__version__}, warp {wp.__version__} (CPU)",
                vertex_pairs=pairs if solver_name == "xpbd" and len(pairs) else None)
