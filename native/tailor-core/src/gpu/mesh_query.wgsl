// The particle-vs-cell test against the mesh colliders' hash (port of
// `MeshCollider::contact`), shared by contact detection and the end-of-substep resolve.
// Bindings 10-13 are reserved for it in the stages that include it.
//
// `mverts` sections (vec4 each): previous frame positions [0, V), next [V, 2V), this
// substep's [2V, 3V), vertex velocities during the frame [3V, 4V), then one unit normal per
// triangle (zero for zero-area ones) from 4V on. Triangle vertices in `idx` are global.

@group(0) @binding(10) var<uniform> meshes: Meshes;
@group(0) @binding(11) var<storage, read> idx: array<u32>;
@group(0) @binding(12) var<storage, read> mverts: array<vec4<f32>>;
@group(0) @binding(13) var<storage, read> mtable: array<u32>;

struct MeshHit {
    found: u32,
    depth: f32,
    tri: u32,
    target_pos: vec3<f32>,
    normal: vec3<f32>,
    bary: vec3<f32>,
}

fn mesh_vertex_index(gt: u32, k: u32) -> u32 {
    return idx[params.mesh_tris + 3u * gt + k];
}

fn mesh_cur(v: u32) -> vec3<f32> {
    return mverts[2u * params.n_mesh_verts + v].xyz;
}

// Whether table entry `e` is filed in `cell`, and (w) its primitive.
fn entry_cell_matches(e: u32, cell: vec3<i32>) -> bool {
    let k = meshes.entries_off + 4u * e;
    return mtable[k] == bitcast<u32>(cell.x) && mtable[k + 1u] == bitcast<u32>(cell.y) && mtable[k + 2u] == bitcast<u32>(cell.z);
}

// Mesh collider `c` at p for a particle of collision level `level` (port of
// `geometry::nearest_feature_contact`): the nearest (level-filtered, non-degenerate) triangle
// of p's cell decides; found when p is behind its plane offset by `thickness` and behind the
// offset plane of every candidate sharing its closest point; the target is p moved along the
// normal onto that plane (geometry.rs `particle_vs_cell` says why).
fn candidate_triangle(e: u32, cell: vec3<i32>, mi: MeshInfo, level: i32) -> u32 {
    if (!entry_cell_matches(e, cell)) {
        return 0xffffffffu;
    }
    let t = mtable[meshes.entries_off + 4u * e + 3u];
    let gt = mi.tri_off + t;
    if (!levels_collide(level, bitcast<i32>(idx[params.tri_levels + gt]))) {
        return 0xffffffffu;
    }
    if (all(mverts[4u * params.n_mesh_verts + gt].xyz == vec3<f32>(0.0))) {
        return 0xffffffffu;
    }
    return t;
}

fn no_hit() -> MeshHit {
    return MeshHit(0u, 0.0, 0u, vec3<f32>(0.0), vec3<f32>(0.0), vec3<f32>(0.0));
}

fn mesh_contact(c: u32, p: vec3<f32>, level: i32, thickness: f32) -> MeshHit {
    let mi = meshes.m[c];
    let cell = cell_of(p, mi.cell);
    let b = mi.bucket_off + bucket_of(cell, mi.mask);
    let e0 = mtable[b];
    let e1 = mtable[b + 1u];
    let nt_base = 4u * params.n_mesh_verts;
    // Pass 1: side tests only (in front of every offset plane: free), and the candidate whose
    // plane is nearest, which seeds the search.
    var any_behind = false;
    var seed = 0xffffffffu;
    var seed_side = 0.0;
    for (var e = e0; e < e1; e++) {
        let t = candidate_triangle(e, cell, mi, level);
        if (t == 0xffffffffu) {
            continue;
        }
        let gt = mi.tri_off + t;
        let side = dot(p - mesh_cur(mesh_vertex_index(gt, 0u)), mverts[nt_base + gt].xyz);
        any_behind = any_behind || side < thickness;
        if (seed == 0xffffffffu || abs(side) < seed_side) {
            seed = t;
            seed_side = abs(side);
        }
    }
    if (seed == 0xffffffffu || !any_behind) {
        return no_hit();
    }
    let g0 = mi.tri_off + seed;
    var ta = mesh_cur(mesh_vertex_index(g0, 0u));
    var tb = mesh_cur(mesh_vertex_index(g0, 1u));
    var tc = mesh_cur(mesh_vertex_index(g0, 2u));
    let cl0 = closest_point_on_triangle(p, ta, tb, tc);
    var bd2 = dot(cl0.q - p, cl0.q - p);
    var hit = MeshHit(1u, 0.0, seed, cl0.q, mverts[nt_base + g0].xyz, cl0.bary);
    // Pass 2: the nearest candidate, unless the seed's projection lies inside it (then no
    // candidate is nearer than its plane); those whose plane is farther than the best are
    // skipped.
    if (!all(cl0.bary > vec3<f32>(0.0))) {
        for (var e = e0; e < e1; e++) {
            let t = candidate_triangle(e, cell, mi, level);
            if (t == 0xffffffffu || t == seed) {
                continue;
            }
            let gt = mi.tri_off + t;
            let n = mverts[nt_base + gt].xyz;
            let a = mesh_cur(mesh_vertex_index(gt, 0u));
            let side = dot(p - a, n);
            if (side * side >= bd2) {
                continue;
            }
            let bb = mesh_cur(mesh_vertex_index(gt, 1u));
            let cc = mesh_cur(mesh_vertex_index(gt, 2u));
            let cl = closest_point_on_triangle(p, a, bb, cc);
            let d2 = dot(cl.q - p, cl.q - p);
            if (d2 < bd2) {
                bd2 = d2;
                hit = MeshHit(1u, 0.0, t, cl.q, n, cl.bary);
                ta = a;
                tb = bb;
                tc = cc;
            }
        }
    }
    let q = hit.target_pos;
    let depth = thickness - dot(p - q, hit.normal);
    if (depth <= 0.0) {
        return no_hit();
    }
    // Pass 3, only for a closest point on (or within a few SHARED_FEATURE of) an edge: a
    // candidate in front of its offset plane sharing it (a convex ridge) frees the particle.
    let twice_area = length(cross(tb - ta, tc - ta));
    let edges = vec3<f32>(length(tc - tb), length(ta - tc), length(tb - ta));
    if (any(hit.bary * twice_area <= 2.0 * SHARED_FEATURE * edges)) {
        for (var e = e0; e < e1; e++) {
            let t = candidate_triangle(e, cell, mi, level);
            if (t == 0xffffffffu) {
                continue;
            }
            let gt = mi.tri_off + t;
            let a = mesh_cur(mesh_vertex_index(gt, 0u));
            let side = dot(p - a, mverts[nt_base + gt].xyz);
            if (side < thickness || side > sqrt(bd2) + SHARED_FEATURE) {
                continue;
            }
            let cl = closest_point_on_triangle(p, a, mesh_cur(mesh_vertex_index(gt, 1u)), mesh_cur(mesh_vertex_index(gt, 2u)));
            let dq = cl.q - q;
            if (dot(dq, dq) <= SHARED_FEATURE * SHARED_FEATURE) {
                return no_hit();
            }
        }
    }
    hit.depth = depth;
    hit.target_pos = p + hit.normal * depth;
    return hit;
}

// Two candidates whose closest points are closer than this (m) share a feature
// (`geometry::SHARED_FEATURE`).
const SHARED_FEATURE: f32 = 1e-5;

// The deepest mesh contact of a particle over all mesh colliders (`find_mesh_contacts`);
// `collider` receives the collider's index.
struct DeepestHit {
    hit: MeshHit,
    collider: u32,
}

fn deepest_mesh_contact(p: vec3<f32>, level: i32) -> DeepestHit {
    var best = DeepestHit(MeshHit(0u, 0.0, 0u, vec3<f32>(0.0), vec3<f32>(0.0), vec3<f32>(0.0)), 0u);
    for (var c = 0u; c < params.n_meshes; c++) {
        let h = mesh_contact(c, p, level, params.thickness);
        if (h.found != 0u && (best.hit.found == 0u || h.depth > best.hit.depth)) {
            best = DeepestHit(h, c);
        }
    }
    return best;
}

// Cells a crossing test walks at most (`mesh_collider::MAX_CROSSING_CELLS`).
const MAX_CROSSING_CELLS: u32 = 1024u;

// Mesh collider `c` crossed front to back by the motion from `x0` to `x1` (port of
// `MeshCollider::crossing`): the first triangle the segment passes through, found by walking
// the cells it passes through (`hash::segment_cells`, each cell's candidates as in
// `mesh_contact`); the target is `x1` moved back along that triangle's normal to `thickness`
// in front of its plane. No hit when it crosses none within MAX_CROSSING_CELLS cells.
fn mesh_crossing(c: u32, x0: vec3<f32>, x1: vec3<f32>, level: i32, thickness: f32) -> MeshHit {
    let mi = meshes.m[c];
    let l = mi.cell;
    let d = x1 - x0;
    var cell = cell_of(x0, l);
    let end = cell_of(x1, l);
    // Per axis: the step, the segment parameter of the next cell face, and between faces.
    var step = vec3<i32>(0);
    var next = vec3<f32>(F32_MAX);
    var delta = vec3<f32>(F32_MAX);
    for (var k = 0; k < 3; k++) {
        if (cell[k] != end[k] && d[k] != 0.0) {
            step[k] = select(-1, 1, d[k] > 0.0);
            let face = f32(cell[k] + select(0, 1, d[k] > 0.0)) * l;
            next[k] = max((face - x0[k]) / d[k], 0.0);
            delta[k] = l / abs(d[k]);
        }
    }
    let nt_base = 4u * params.n_mesh_verts;
    var best = no_hit();
    var best_s = 0.0;
    for (var walked = 0u; walked < MAX_CROSSING_CELLS; walked++) {
        let b = mi.bucket_off + bucket_of(cell, mi.mask);
        let e0 = mtable[b];
        let e1 = mtable[b + 1u];
        for (var e = e0; e < e1; e++) {
            let t = candidate_triangle(e, cell, mi, level);
            if (t == 0xffffffffu) {
                continue;
            }
            let gt = mi.tri_off + t;
            let n = mverts[nt_base + gt].xyz;
            let a = mesh_cur(mesh_vertex_index(gt, 0u));
            let side_from = dot(x0 - a, n);
            let side_to = dot(x1 - a, n);
            if (!(side_from >= 0.0 && side_to < 0.0)) {
                continue;
            }
            let s = side_from / (side_from - side_to);
            if (best.found != 0u && s >= best_s) {
                continue;
            }
            let q = x0 + d * s;
            let cl = closest_point_on_triangle(q, a, mesh_cur(mesh_vertex_index(gt, 1u)), mesh_cur(mesh_vertex_index(gt, 2u)));
            // The crossing point lies on the triangle (to rounding), not only on its plane.
            let dq = cl.q - q;
            if (dot(dq, dq) > (1e-4 * l) * (1e-4 * l)) {
                continue;
            }
            let depth = thickness - side_to;
            best = MeshHit(1u, depth, t, x1 + n * depth, n, cl.bary);
            best_s = s;
        }
        if (all(cell == end)) {
            break;
        }
        // The axis whose face comes first; an axis already at its end cell never steps.
        var k = -1;
        var kn = 0.0;
        for (var a = 0; a < 3; a++) {
            if (cell[a] != end[a] && (k < 0 || next[a] < kn)) {
                k = a;
                kn = next[a];
            }
        }
        if (k < 0) {
            break;
        }
        cell[k] += step[k];
        next[k] += delta[k];
    }
    return best;
}

// The deepest crossing over all mesh colliders (`find_mesh_contacts` with crossings).
fn deepest_mesh_crossing(x0: vec3<f32>, x1: vec3<f32>, level: i32) -> DeepestHit {
    var best = DeepestHit(no_hit(), 0u);
    for (var c = 0u; c < params.n_meshes; c++) {
        let h = mesh_crossing(c, x0, x1, level, params.thickness);
        if (h.found != 0u && (best.hit.found == 0u || h.depth > best.hit.depth)) {
            best = DeepestHit(h, c);
        }
    }
    return best;
}
