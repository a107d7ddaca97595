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

// Mesh collider `c` at p for a particle of collision level `level`: found when p is behind
// every (level-filtered, non-degenerate) triangle of its cell offset by `thickness`; then the
// nearest of them gives the depth and the target (p moved along the normal onto the offset
// plane; geometry.rs `particle_vs_cell` says why not the closest point).
fn mesh_contact(c: u32, p: vec3<f32>, level: i32, thickness: f32) -> MeshHit {
    let mi = meshes.m[c];
    var hit = MeshHit(0u, 0.0, 0u, vec3<f32>(0.0), vec3<f32>(0.0), vec3<f32>(0.0));
    let cell = cell_of(p, mi.cell);
    let b = mi.bucket_off + bucket_of(cell, mi.mask);
    let e0 = mtable[b];
    let e1 = mtable[b + 1u];
    let nt_base = 4u * params.n_mesh_verts;
    // Pass 1: side tests only; a particle in front of any candidate leaves at once.
    var behind = false;
    for (var e = e0; e < e1; e++) {
        if (!entry_cell_matches(e, cell)) {
            continue;
        }
        let gt = mi.tri_off + mtable[meshes.entries_off + 4u * e + 3u];
        if (!levels_collide(level, bitcast<i32>(idx[params.tri_levels + gt]))) {
            continue;
        }
        let n = mverts[nt_base + gt].xyz;
        if (all(n == vec3<f32>(0.0))) {
            continue;
        }
        if (dot(p - mesh_cur(mesh_vertex_index(gt, 0u)), n) >= thickness) {
            return hit;
        }
        behind = true;
    }
    if (!behind) {
        return hit;
    }
    // Pass 2: the nearest candidate (first of equals, candidates in triangle order).
    var bd2 = 0.0;
    for (var e = e0; e < e1; e++) {
        if (!entry_cell_matches(e, cell)) {
            continue;
        }
        let t = mtable[meshes.entries_off + 4u * e + 3u];
        let gt = mi.tri_off + t;
        if (!levels_collide(level, bitcast<i32>(idx[params.tri_levels + gt]))) {
            continue;
        }
        let n = mverts[nt_base + gt].xyz;
        if (all(n == vec3<f32>(0.0))) {
            continue;
        }
        let a = mesh_cur(mesh_vertex_index(gt, 0u));
        let bb = mesh_cur(mesh_vertex_index(gt, 1u));
        let cc = mesh_cur(mesh_vertex_index(gt, 2u));
        let cl = closest_point_on_triangle(p, a, bb, cc);
        let dq = cl.q - p;
        let d2 = dot(dq, dq);
        if (hit.found == 0u || d2 < bd2) {
            bd2 = d2;
            let depth = thickness - dot(p - cl.q, n);
            hit = MeshHit(1u, depth, t, p + n * depth, n, cl.bary);
        }
    }
    return hit;
}

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
