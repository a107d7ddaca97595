// Declarations shared by every Tailor compute shader (prepended to each one).
// Mirrored by `common.rs`: keep the field order and padding identical.

struct Params {
    gravity: vec3<f32>,
    h: f32,
    inv_h: f32,
    inv_h2: f32,
    rho: f32,
    n: u32,
    n_tris: u32,
    n_seam_pairs: u32,
    delay: u32,
    ramp_enabled: u32,
    air_damping: f32,
    closing_damping: f32,
    gap_threshold: f32,
    closed_fraction: f32,
    release_time: f32,
    has_seams: u32,
    // Section bases in the packed index buffer `idx`.
    mat_off: u32,
    mat_cols: u32,
    slot_off: u32,
    slot_idx: u32,
    tri_verts: u32,
    seam_off: u32,
    seam_verts: u32,
    order: u32,
    // Section bases in the packed float buffer `fdata`.
    mat_vals: u32,
    diag: u32,
    tri_data: u32,
    seam_coefs: u32,
    // Curved (creased-rest) stencils: count, rows and vertices in `idx`; coefficients and
    // (weight, rest) pairs in `fdata`. Their slots follow the triangles' in row order.
    n_curved: u32,
    curved_off: u32,
    curved_verts: u32,
    curved_coefs: u32,
    curved_wr: u32,
    n_colliders: u32,
    thickness: f32,
    substeps: u32,
    // Mesh colliders (`collide_common.wgsl`): counts, and sections of `idx`: triangle
    // vertices (global), triangle levels, particle levels, pinned flags.
    n_meshes: u32,
    n_mesh_verts: u32,
    n_mesh_tris: u32,
    mesh_tris: u32,
    tri_levels: u32,
    particle_levels: u32,
    pinned: u32,
    // Per-particle friction (static, kinetic) pairs in `fdata`, when has_friction != 0.
    has_friction: u32,
    friction: u32,
    // Self-collision: sphere radius, hash cell, default friction, bucket mask of the particle
    // hash, and the exclusion set (CSR rows and neighbours in `idx`).
    self_enabled: u32,
    self_radius: f32,
    self_cell: f32,
    self_mu_s: f32,
    self_mu_k: f32,
    self_mask: u32,
    excl_off: u32,
    excl_nbr: u32,
    iterations: u32,
    // The seam-closing ramp (`SeamRamp`): the widest gap that releases it, the factor on
    // gravity while seams close, the widest pair's closing speed (m/s), and whether pairs
    // were still on their closing schedule at upload (`close_seams.wgsl` runs then).
    release_gap: f32,
    closing_gravity: f32,
    closing_speed: f32,
    closing_scheduled: u32,
    // The two-level step's coarse grid (`coarse.wgsl`; n_coarse 0: off): its size and CG
    // iterations; sections of `idx`: each particle's aggregate, each aggregate's members
    // (rows, members), the coarse matrix's rows and columns; of `fdata`: its values and its
    // diagonal without contacts.
    n_coarse: u32,
    coarse_iterations: u32,
    coarse_agg: u32,
    coarse_member_off: u32,
    coarse_members: u32,
    coarse_off: u32,
    coarse_cols: u32,
    coarse_vals: u32,
    coarse_diag0: u32,
    _pad_coarse0: u32,
    _pad_coarse1: u32,
    _pad_coarse2: u32,
}

// Per-substep iteration state and the seam-closing ramp, owned by the GPU.
struct StepState {
    omega: f32,
    last_delta: f32,
    started: u32,
    k: u32,
    r0: f32,
    residual: f32,
    phase: u32,
    elapsed: f32,
    gap_max: f32,
    closed_fraction: f32,
    contacts: u32,
    // Substep of the frame being run (wraps to 0 after the last).
    substep: u32,
    mesh_contacts: u32,
    self_pairs: u32,
    // Early stop: `reduce_omega` sets `stop` when the substep has converged (the CPU's test in
    // `Simulation::iterate`); `gate`, first in the next iteration, turns it into `done`, which
    // every iteration stage reads before doing anything. `predict` clears both.
    done: u32,
    stop: u32,
    tolerance: f32,
    // The cloth's weight, ‖m·g‖ over the free particles: the residual's floor in the test.
    weight_norm: f32,
    // Iterations run in the frame (the host clears it before the frame).
    iterations_run: u32,
    // The fastest particle's speed after the frame's last substep, as f32 bits (positive
    // floats order as their bits): the CPU's sleep test (`sleep.rs`). Cleared per frame.
    max_speed_bits: atomic<u32>,
    // Some seam pair still has closing schedule left (`Simulation::seams_closing`).
    closing: u32,
    // The ramp's stall watch (`Ramp::stalled`): on, the smallest widest gap so far, and the
    // seconds since it last shrank.
    stall_on: u32,
    stall_best: f32,
    stall_since: f32,
    // The substep's first sweep's update norm, and whether an update outgrew it RUNAWAY times (then plain
    // sweeps to the substep's end: `Chebyshev::omega`).
    first_delta: f32,
    diverging: u32,
}

const PHASE_CLOSING: u32 = 0u;
const PHASE_RELEASING: u32 = 1u;
const PHASE_DONE: u32 = 2u;
// WGSL has no infinity literal; the largest f32 compares the same way here.
const F32_MAX: f32 = 3.40282347e38;

// An analytic collider (port of `contacts::Shape`): plane (p0 = point, p1 = normal), sphere
// (p0 = centre) or capsule (segment p0-p1), with its radius and friction coefficients.
struct Collider {
    p0: vec3<f32>,
    radius: f32,
    p1: vec3<f32>,
    kind: u32,
    static_friction: f32,
    kinetic_friction: f32,
    _pad0: u32,
    _pad1: u32,
}

// A particle's contact this iteration: target and weight (0 = none), normal and collider
// (analytic index, or MESH_CONTACT | mesh collider), and for mesh contacts the touched
// triangle (collider-local) and the barycentrics of the closest point (for friction).
struct Contact {
    target_pos: vec3<f32>,
    weight: f32,
    normal: vec3<f32>,
    collider: u32,
    bary: vec3<f32>,
    tri: u32,
}

// Static per-particle data.
struct Particle {
    b_const: vec3<f32>,
    mass: f32,
    pin_target: vec3<f32>,
    // PARTICLE_PINNED | PARTICLE_SEWN
    flags: u32,
}

// `common::PARTICLE_PINNED`, `common::PARTICLE_SEWN`.
const PARTICLE_PINNED: u32 = 1u;
const PARTICLE_SEWN: u32 = 2u;

const KIND_PLANE: u32 = 0u;
const KIND_SPHERE: u32 = 1u;
const KIND_CAPSULE: u32 = 2u;
const NO_COLLIDER: u32 = 0xffffffffu;
// `collide::MESH_CONTACT`: the contact is with mesh collider `collider & ~MESH_CONTACT`.
const MESH_CONTACT: u32 = 0x80000000u;

// Whether a contact is with an analytic collider (port of the CPU's `c & MESH_CONTACT == 0`).
fn is_analytic(c: u32) -> bool {
    return c != NO_COLLIDER && (c & MESH_CONTACT) == 0u;
}

fn is_mesh(c: u32) -> bool {
    return c != NO_COLLIDER && (c & MESH_CONTACT) != 0u;
}

fn sphere_distance(p: vec3<f32>, c: vec3<f32>, r: f32) -> vec4<f32> {
    let d = p - c;
    let l = length(d);
    var n = vec3<f32>(0.0, 0.0, 1.0);
    if (l > 1e-12) {
        n = d / l;
    }
    return vec4<f32>(n, l - r);
}

// Signed distance (w) and outward unit normal (xyz) at p (port of `Shape::distance`).
fn collider_distance(c: Collider, p: vec3<f32>) -> vec4<f32> {
    if (c.kind == KIND_PLANE) {
        // glam's normalize_or: v · (1/|v|), Z when that is not finite and positive.
        let l = length(c.p1);
        var n = vec3<f32>(0.0, 0.0, 1.0);
        if (l > 0.0) {
            n = c.p1 * (1.0 / l);
        }
        return vec4<f32>(n, dot(p - c.p0, n));
    }
    if (c.kind == KIND_SPHERE) {
        return sphere_distance(p, c.p0, c.radius);
    }
    let ab = c.p1 - c.p0;
    let t = clamp(dot(p - c.p0, ab) / max(dot(ab, ab), 1e-20), 0.0, 1.0);
    return sphere_distance(p, c.p0 + ab * t, c.radius);
}

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var<storage, read_write> state: StepState;

// Air damping in effect for a ramp phase, 1/s (port of `damping::Ramp::damping`).
// Whether the ramp holds the seams' closing now (`Simulation::ramp_closing`).
fn ramp_closing() -> bool {
    return params.ramp_enabled != 0u && params.has_seams != 0u && state.phase == PHASE_CLOSING;
}

// Gravity in effect now (`Ramp::gravity_scale`): `closing_gravity` times it while seams close.
fn gravity_now() -> vec3<f32> {
    var scale = 1.0;
    if (ramp_closing()) {
        scale = params.closing_gravity;
    }
    return params.gravity * scale;
}

fn ramp_damping(phase: u32, elapsed: f32) -> f32 {
    if (params.ramp_enabled == 0u) {
        return params.air_damping;
    }
    let high = max(params.closing_damping, params.air_damping);
    if (phase == PHASE_CLOSING) {
        return high;
    }
    if (phase == PHASE_RELEASING) {
        var t = 1.0;
        if (params.release_time > 0.0) {
            t = min(elapsed / params.release_time, 1.0);
        }
        return high + (params.air_damping - high) * t;
    }
    return params.air_damping;
}
