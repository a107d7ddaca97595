// The mesh colliders' spatial hash, built on the GPU (Eq. 1-3, Alg. 1) whenever a collider
// moves (every substep then) or after an upload:
//
// 1. `lerp` (per collider vertex): this substep's positions, (1 − α)·prev + α·next with
//    α = (k + 1)/K (the CPU's `MeshCollider::prepare`); at the first substep the frame's
//    vertex velocities (next − prev)/dt, at the last prev ← next for the next frame;
// 2. `count` (per triangle): the triangle's unit normal, and +1 in the bucket of every cell
//    of its padded AABB the insertion rule keeps (`collider_filing::Filing`);
// 3. `hash.wgsl` `scan`: bucket starts by a prefix sum, counts become insertion cursors;
// 4. `scatter` (per triangle): the same cells again, each entry written at its bucket's
//    cursor (atomic add);
// 5. `hash.wgsl` `sort`: each bucket sorted by (cell, triangle), so queries see a cell's
//    triangles in increasing order, as on the CPU, whatever the scatter's schedule.
//
// Triangles are not culled to the cloth's box as on the CPU: culling never changes a contact
// there (see `mesh_collider.rs`), and the GPU files every triangle in parallel anyway.

@group(0) @binding(2) var<uniform> meshes: Meshes;
@group(0) @binding(3) var<storage, read> idx: array<u32>;
@group(0) @binding(4) var<storage, read_write> mverts: array<vec4<f32>>;
@group(0) @binding(5) var<storage, read_write> counts: array<atomic<u32>>;
@group(0) @binding(6) var<storage, read_write> mtable: array<u32>;

fn mesh_of_vertex(v: u32) -> u32 {
    for (var c = 0u; c + 1u < params.n_meshes; c++) {
        if (v < meshes.m[c].vert_off + meshes.m[c].n_verts) {
            return c;
        }
    }
    return params.n_meshes - 1u;
}

fn mesh_of_triangle(t: u32) -> u32 {
    for (var c = 0u; c + 1u < params.n_meshes; c++) {
        if (t < meshes.m[c].tri_off + meshes.m[c].n_tris) {
            return c;
        }
    }
    return params.n_meshes - 1u;
}

@compute @workgroup_size(64)
fn lerp(@builtin(global_invocation_id) gid: vec3<u32>) {
    let v = gid.x;
    let nv = params.n_mesh_verts;
    if (v >= nv) {
        return;
    }
    let mi = meshes.m[mesh_of_vertex(v)];
    let a = mverts[v].xyz;
    let b = mverts[nv + v].xyz;
    if (mi.moving != 0u) {
        if (state.substep == 0u) {
            mverts[3u * nv + v] = vec4<f32>((b - a) * meshes.inv_dt, 0.0);
        }
        let alpha = f32(state.substep + 1u) / f32(params.substeps);
        // glam's `lerp`: a·(1 − α) + b·α.
        mverts[2u * nv + v] = vec4<f32>(a * (1.0 - alpha) + b * alpha, 0.0);
        if (state.substep + 1u == params.substeps) {
            mverts[v] = vec4<f32>(b, 0.0);
        }
    } else {
        mverts[2u * nv + v] = vec4<f32>(b, 0.0);
        mverts[3u * nv + v] = vec4<f32>(0.0);
    }
}

struct TriCells {
    t0: vec3<f32>,
    t1: vec3<f32>,
    t2: vec3<f32>,
    lo: vec3<i32>,
    hi: vec3<i32>,
}

fn triangle_cells(gt: u32, l: f32) -> TriCells {
    let cur = 2u * params.n_mesh_verts;
    let t0 = mverts[cur + idx[params.mesh_tris + 3u * gt]].xyz;
    let t1 = mverts[cur + idx[params.mesh_tris + 3u * gt + 1u]].xyz;
    let t2 = mverts[cur + idx[params.mesh_tris + 3u * gt + 2u]].xyz;
    let pad = PAD * l;
    let lo = min(min(t0, t1), t2) - pad;
    let hi = max(max(t0, t1), t2) + pad;
    return TriCells(t0, t1, t2, cell_of(lo, l), cell_of(hi, l));
}

@compute @workgroup_size(64)
fn count(@builtin(global_invocation_id) gid: vec3<u32>) {
    let gt = gid.x;
    if (gt >= params.n_mesh_tris) {
        return;
    }
    let mi = meshes.m[mesh_of_triangle(gt)];
    let l = mi.cell;
    let tc = triangle_cells(gt, l);
    mverts[4u * params.n_mesh_verts + gt] = vec4<f32>(triangle_normal(tc.t0, tc.t1, tc.t2), 0.0);
    for (var z = tc.lo.z; z <= tc.hi.z; z++) {
        for (var y = tc.lo.y; y <= tc.hi.y; y++) {
            for (var x = tc.lo.x; x <= tc.hi.x; x++) {
                let cell = vec3<i32>(x, y, z);
                if (keeps_cell(tc.t0, tc.t1, tc.t2, cell, l, PAD * l, mi.rule)) {
                    atomicAdd(&counts[mi.bucket_off + bucket_of(cell, mi.mask)], 1u);
                }
            }
        }
    }
}

@compute @workgroup_size(64)
fn scatter(@builtin(global_invocation_id) gid: vec3<u32>) {
    let gt = gid.x;
    if (gt >= params.n_mesh_tris) {
        return;
    }
    let mi = meshes.m[mesh_of_triangle(gt)];
    let l = mi.cell;
    let tc = triangle_cells(gt, l);
    for (var z = tc.lo.z; z <= tc.hi.z; z++) {
        for (var y = tc.lo.y; y <= tc.hi.y; y++) {
            for (var x = tc.lo.x; x <= tc.hi.x; x++) {
                let cell = vec3<i32>(x, y, z);
                if (keeps_cell(tc.t0, tc.t1, tc.t2, cell, l, PAD * l, mi.rule)) {
                    let pos = atomicAdd(&counts[mi.bucket_off + bucket_of(cell, mi.mask)], 1u);
                    let k = meshes.entries_off + 4u * pos;
                    mtable[k] = bitcast<u32>(x);
                    mtable[k + 1u] = bitcast<u32>(y);
                    mtable[k + 2u] = bitcast<u32>(z);
                    mtable[k + 3u] = gt - mi.tri_off;
                }
            }
        }
    }
}
