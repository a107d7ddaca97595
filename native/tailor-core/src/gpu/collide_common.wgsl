// Declarations shared by the collision stages (prepended after `common.wgsl`): the spatial
// hash of Eq. 1-3 on the GPU, the mesh colliders' layout, and the point-triangle kernels.
// Mirrored by `collide_common.rs`.
//
// A hash table is three things: `counts` (one atomic u32 per bucket: sizes while building,
// then insertion cursors, zeroed again by the sort), and `table` = the bucket starts
// (n_buckets + 1 u32) followed by the entries, 4 u32 each: the cell's integer coordinates
// (bitcast i32) and the primitive. Queries compare the whole cell, never a lossy id, so
// cells sharing a bucket are never confused (stricter than the CPU's 64-bit Eq. 3 id, which
// is exact for every cell a scene reaches).

// A mesh collider: where its vertices and triangles sit in the global sections, its hash
// cell side and bucket range, its insertion rule and friction, and whether it moves this
// frame. 48 bytes.
struct MeshInfo {
    cell: f32,
    vert_off: u32,
    n_verts: u32,
    tri_off: u32,
    n_tris: u32,
    bucket_off: u32,
    mask: u32,
    rule: u32,
    moving: u32,
    static_friction: f32,
    kinetic_friction: f32,
    _pad0: u32,
}

const MAX_MESHES: u32 = 8u;

// Per-frame collider data (uniform): 1/dt for the collider velocities, then the colliders.
struct Meshes {
    inv_dt: f32,
    // Where the entries start in the collider table (its bucket count + 1).
    entries_off: u32,
    _pad1: u32,
    _pad2: u32,
    m: array<MeshInfo, 8>,
}

// One hash table's size (uniform, one per table).
struct TableInfo {
    n_buckets: u32,
    n_entries: u32,
    _pad0: u32,
    _pad1: u32,
}

// Insertion rules (`collider_hash::InsertionRule`).
const RULE_PAPER: u32 = 0u;
const RULE_PAPER_OR_PLANE: u32 = 1u;
const RULE_AABB: u32 = 2u;

// Eq. 1 primes (Teschner et al. 2003).
const P1: u32 = 73856093u;
const P2: u32 = 19349663u;
const P3: u32 = 83492791u;

// Cell coordinates are clamped to ±1e9 (the CPU clamps its i64 cells at ±4.6e18); cells
// that far out differ, nothing a scene reaches does.
const CELL_CLAMP: f32 = 1.0e9;

// Eq. 2: the cell containing p (the CPU's `hash::cell_of`).
fn cell_of(p: vec3<f32>, l: f32) -> vec3<i32> {
    let q = clamp(p / l, vec3<f32>(-CELL_CLAMP), vec3<f32>(CELL_CLAMP));
    return vec3<i32>(floor(q));
}

// Eq. 1 for a table of mask + 1 buckets, equal to the CPU's `hash::bucket_of` on the same
// cell: the CPU multiplies in wrapping i64, takes |h| and masks. With |c| < 2^31 the
// products c·p do not wrap, so each one's sign is the sign of c, the xor's sign is the xor of
// those, and the low 32 bits of the products (all the mask keeps) are the u32 products.
// |h| negates a negative h, whose low 32 bits are then 0 − (low 32 bits of h).
fn bucket_of(c: vec3<i32>, mask: u32) -> u32 {
    var h = (bitcast<u32>(c.x) * P1) ^ (bitcast<u32>(c.y) * P2) ^ (bitcast<u32>(c.z) * P3);
    let neg = (c.x < 0) != ((c.y < 0) != (c.z < 0));
    if (neg) {
        h = 0u - h;
    }
    return h & mask;
}

// Triangle filing (port of `collider_filing::Filing`): Alg. 1's vertex test, else (rule
// paper-or-plane) the plane-box test widened by `pad`.
fn keeps_cell(t0: vec3<f32>, t1: vec3<f32>, t2: vec3<f32>, cell: vec3<i32>, l: f32, pad: f32, rule: u32) -> bool {
    if (rule == RULE_AABB) {
        return true;
    }
    let centre = (vec3<f32>(cell) + 0.5) * l;
    let r2 = 0.5 * l * l;
    let d0 = t0 - centre;
    let d1 = t1 - centre;
    let d2 = t2 - centre;
    if (dot(d0, d0) < r2 || dot(d1, d1) < r2 || dot(d2, d2) < r2) {
        return true;
    }
    if (rule != RULE_PAPER_OR_PLANE) {
        return false;
    }
    let n = cross(t1 - t0, t2 - t0);
    return abs(dot(n, centre - t0)) <= 0.5 * l * (abs(n.x) + abs(n.y) + abs(n.z)) + pad * length(n);
}

// The CPU's `mesh_collider::PAD`: triangles are filed in their AABB grown by PAD·l.
const PAD: f32 = 0.25;

// Unit normal of abc, zero for a zero-area triangle (glam's `try_normalize`).
fn triangle_normal(a: vec3<f32>, b: vec3<f32>, c: vec3<f32>) -> vec3<f32> {
    let n = cross(b - a, c - a);
    let rcp = 1.0 / length(n);
    if (rcp > 0.0 && rcp < F32_MAX) {
        return n * rcp;
    }
    return vec3<f32>(0.0);
}

// Closest point on a triangle and its barycentrics (port of
// `geometry::closest_point_on_triangle`, Ericson 5.1.5, with its degenerate fallback).
struct Closest {
    q: vec3<f32>,
    bary: vec3<f32>,
}

fn closest_on_segment(p: vec3<f32>, a: vec3<f32>, b: vec3<f32>) -> vec4<f32> {
    let ab = b - a;
    let len2 = dot(ab, ab);
    var t = 0.0;
    if (len2 > 0.0) {
        t = clamp(dot(p - a, ab) / len2, 0.0, 1.0);
    }
    return vec4<f32>(a + ab * t, t);
}

fn closest_on_degenerate(p: vec3<f32>, a: vec3<f32>, b: vec3<f32>, c: vec3<f32>) -> Closest {
    let s0 = closest_on_segment(p, a, b);
    let s1 = closest_on_segment(p, b, c);
    let s2 = closest_on_segment(p, c, a);
    var best = Closest(s0.xyz, vec3<f32>(1.0 - s0.w, s0.w, 0.0));
    let e0 = s0.xyz - p;
    var bd = dot(e0, e0);
    let e1 = s1.xyz - p;
    if (dot(e1, e1) < bd) {
        best = Closest(s1.xyz, vec3<f32>(0.0, 1.0 - s1.w, s1.w));
        bd = dot(e1, e1);
    }
    let e2 = s2.xyz - p;
    if (dot(e2, e2) < bd) {
        best = Closest(s2.xyz, vec3<f32>(s2.w, 0.0, 1.0 - s2.w));
    }
    return best;
}

const F32_EPSILON: f32 = 1.1920929e-7;

fn closest_point_on_triangle(p: vec3<f32>, a: vec3<f32>, b: vec3<f32>, c: vec3<f32>) -> Closest {
    let ab = b - a;
    let ac = c - a;
    let cr = cross(ab, ac);
    if (dot(cr, cr) <= F32_EPSILON * F32_EPSILON * dot(ab, ab) * dot(ac, ac)) {
        return closest_on_degenerate(p, a, b, c);
    }
    let ap = p - a;
    let d1 = dot(ab, ap);
    let d2 = dot(ac, ap);
    if (d1 <= 0.0 && d2 <= 0.0) {
        return Closest(a, vec3<f32>(1.0, 0.0, 0.0));
    }
    let bp = p - b;
    let d3 = dot(ab, bp);
    let d4 = dot(ac, bp);
    if (d3 >= 0.0 && d4 <= d3) {
        return Closest(b, vec3<f32>(0.0, 1.0, 0.0));
    }
    let vc = d1 * d4 - d3 * d2;
    if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) {
        let v = d1 / (d1 - d3);
        return Closest(a + ab * v, vec3<f32>(1.0 - v, v, 0.0));
    }
    let cp = p - c;
    let d5 = dot(ab, cp);
    let d6 = dot(ac, cp);
    if (d6 >= 0.0 && d5 <= d6) {
        return Closest(c, vec3<f32>(0.0, 0.0, 1.0));
    }
    let vb = d5 * d2 - d1 * d6;
    if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) {
        let w = d2 / (d2 - d6);
        return Closest(a + ac * w, vec3<f32>(1.0 - w, 0.0, w));
    }
    let va = d3 * d6 - d5 * d4;
    if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0) {
        let w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return Closest(b + (c - b) * w, vec3<f32>(0.0, 1.0 - w, w));
    }
    let denom = 1.0 / (va + vb + vc);
    let v = vb * denom;
    let w = vc * denom;
    return Closest(a + ab * v + ac * w, vec3<f32>(1.0 - v - w, v, w));
}

// Collision levels (`collide::levels::levels_collide`).
fn levels_collide(a: i32, b: i32) -> bool {
    return a == 0 || b == 0 || a == b;
}
