// Cloth-cloth collisions on the GPU (port of `self_collide.rs`), after each iteration:
//
// 1. `count`, `hash.wgsl` `scan`, `scatter`, `hash.wgsl` `sort`: every particle filed in its
//    cell (side `self_cell` ≥ 2r) of the particle table;
// 2. `gather` (per particle i): the 27 cells around i; every j of those cells (same bucket
//    and same cell) closer than 2r, not excluded (shared triangle, seam partner, neighbour
//    of a seam partner) and of colliding levels is an overlapping pair. Its correction is
//    computed exactly as the CPU does for the pair [min, max] (push along the line of
//    centres by the overlap, split by inverse mass; position-level friction on the pair's
//    relative tangential motion of the substep), and i keeps its own share;
// 3. `apply`: x ← x + (sum of i's shares)/(their count), the CPU's constraint averaging.
//
// The CPU scatters each pair's correction to both particles; here each particle gathers its
// own, so no two threads write one particle and the result does not depend on the schedule.
// The corrections are the same numbers; only the order in which a particle's shares are
// summed differs (the CPU adds them in increasing partner order, the GPU cell by cell),
// which is f32 rounding.

@group(0) @binding(2) var<storage, read_write> x: array<vec4<f32>>;
@group(0) @binding(3) var<storage, read> x_start: array<vec4<f32>>;
@group(0) @binding(4) var<storage, read> particles: array<Particle>;
@group(0) @binding(5) var<storage, read> idx: array<u32>;
@group(0) @binding(6) var<storage, read> fdata: array<f32>;
@group(0) @binding(7) var<storage, read_write> counts: array<atomic<u32>>;
@group(0) @binding(8) var<storage, read_write> stable: array<u32>;
@group(0) @binding(9) var<storage, read_write> sdelta: array<vec4<f32>>;
@group(0) @binding(10) var<storage, read_write> cur: array<vec4<f32>>;
@group(0) @binding(11) var<uniform> table_info: TableInfo;

fn particle_cell(i: u32) -> vec3<i32> {
    return cell_of(x[i].xyz, params.self_cell);
}

@compute @workgroup_size(64)
fn count(@builtin(global_invocation_id) gid: vec3<u32>) {
    // Early stop (`tolerance`): the substep has converged; the pass does nothing more (with
    // `count` skipped the scan and sort that follow see empty buckets: `sort` zeroed them).
    if (state.done != 0u) {
        return;
    }
    let i = gid.x;
    if (i >= params.n) {
        return;
    }
    atomicAdd(&counts[bucket_of(particle_cell(i), table_info.n_buckets - 1u)], 1u);
}

@compute @workgroup_size(64)
fn scatter(@builtin(global_invocation_id) gid: vec3<u32>) {
    // Early stop (`tolerance`): the substep has converged; the pass does nothing more (with
    // `count` skipped the scan and sort that follow see empty buckets: `sort` zeroed them).
    if (state.done != 0u) {
        return;
    }
    let i = gid.x;
    if (i >= params.n) {
        return;
    }
    let c = particle_cell(i);
    let pos = atomicAdd(&counts[bucket_of(c, table_info.n_buckets - 1u)], 1u);
    let k = table_info.n_buckets + 1u + 4u * pos;
    stable[k] = bitcast<u32>(c.x);
    stable[k + 1u] = bitcast<u32>(c.y);
    stable[k + 2u] = bitcast<u32>(c.z);
    stable[k + 3u] = i;
}

// Whether a and b never collide (binary search of b in a's row of the exclusion set).
fn excluded(a: u32, b: u32) -> bool {
    var lo = idx[params.excl_off + a];
    var hi = idx[params.excl_off + a + 1u];
    while (lo < hi) {
        let mid = (lo + hi) / 2u;
        let v = idx[params.excl_nbr + mid];
        if (v == b) {
            return true;
        }
        if (v < b) {
            lo = mid + 1u;
        } else {
            hi = mid;
        }
    }
    return false;
}

fn friction_of(i: u32) -> vec2<f32> {
    if (params.has_friction != 0u) {
        return vec2<f32>(fdata[params.friction + 2u * i], fdata[params.friction + 2u * i + 1u]);
    }
    return vec2<f32>(params.self_mu_s, params.self_mu_k);
}

fn inverse_mass(i: u32) -> f32 {
    let p = particles[i];
    if ((p.flags & PARTICLE_PINNED) != 0u) {
        return 0.0;
    }
    return 1.0 / p.mass;
}

@compute @workgroup_size(64)
fn gather(@builtin(global_invocation_id) gid: vec3<u32>) {
    // Early stop (`tolerance`): the substep has converged; the pass does nothing more (with
    // `count` skipped the scan and sort that follow see empty buckets: `sort` zeroed them).
    if (state.done != 0u) {
        return;
    }
    let i = gid.x;
    if (i >= params.n) {
        return;
    }
    let c = particle_cell(i);
    let mask = table_info.n_buckets - 1u;
    let base = table_info.n_buckets + 1u;
    let two_r = 2.0 * params.self_radius;
    let level_i = bitcast<i32>(idx[params.particle_levels + i]);
    var delta = vec3<f32>(0.0);
    var n_corr = 0u;
    var overlapping = 0u;
    for (var dz = -1; dz <= 1; dz++) {
        for (var dy = -1; dy <= 1; dy++) {
            for (var dx = -1; dx <= 1; dx++) {
                let cc = c + vec3<i32>(dx, dy, dz);
                let b = bucket_of(cc, mask);
                let e1 = stable[b + 1u];
                for (var e = stable[b]; e < e1; e++) {
                    let k = base + 4u * e;
                    if (stable[k] != bitcast<u32>(cc.x) || stable[k + 1u] != bitcast<u32>(cc.y) || stable[k + 2u] != bitcast<u32>(cc.z)) {
                        continue;
                    }
                    let j = stable[k + 3u];
                    if (j == i) {
                        continue;
                    }
                    // The pair as the CPU orders it: a < b.
                    let a = min(i, j);
                    let bb = max(i, j);
                    let xa = x[a].xyz;
                    let xb = x[bb].xyz;
                    let d = xa - xb;
                    if (dot(d, d) >= two_r * two_r) {
                        continue;
                    }
                    let level_j = bitcast<i32>(idx[params.particle_levels + j]);
                    if (excluded(a, bb) || !levels_collide(level_i, level_j)) {
                        continue;
                    }
                    overlapping += 1u;
                    let wa = inverse_mass(a);
                    let wb = inverse_mass(bb);
                    let w = wa + wb;
                    if (w <= 0.0) {
                        continue;
                    }
                    let len = length(d);
                    // Coincident particles: separate along z, the usual layering direction.
                    var nrm = vec3<f32>(0.0, 0.0, 1.0);
                    if (len > 1e-9) {
                        nrm = d / len;
                    }
                    let overlap = two_r - len;
                    var corr = nrm * overlap;
                    let rel = (xa - x_start[a].xyz) - (xb - x_start[bb].xyz);
                    let rel_t = rel - nrm * dot(rel, nrm);
                    let lt = length(rel_t);
                    let fa = friction_of(a);
                    let fb = friction_of(bb);
                    let mu_s = 0.5 * (fa.x + fb.x);
                    let mu_k = 0.5 * (fa.y + fb.y);
                    if (lt > 0.0) {
                        if (lt <= mu_s * overlap) {
                            corr -= rel_t;
                        } else {
                            corr -= rel_t * min(mu_k * overlap / lt, 1.0);
                        }
                    }
                    if (i == a) {
                        delta += corr * (wa / w);
                    } else {
                        delta -= corr * (wb / w);
                    }
                    n_corr += 1u;
                }
            }
        }
    }
    var avg = vec3<f32>(0.0);
    if (n_corr > 0u) {
        avg = delta / f32(n_corr);
    }
    // w: this particle's overlapping pairs (the ramp stage halves their sum for the stats).
    sdelta[i] = vec4<f32>(avg, f32(overlapping));
}

@compute @workgroup_size(64)
fn apply(@builtin(global_invocation_id) gid: vec3<u32>) {
    // Early stop (`tolerance`): the substep has converged; the pass does nothing more (with
    // `count` skipped the scan and sort that follow see empty buckets: `sort` zeroed them).
    if (state.done != 0u) {
        return;
    }
    let i = gid.x;
    if (i >= params.n) {
        return;
    }
    let d = sdelta[i];
    if (d.w > 0.0) {
        let p = vec4<f32>(x[i].xyz + d.xyz, 0.0);
        x[i] = p;
        // Chebyshev's history holds the iterate after the pass, as on the CPU.
        cur[i] = p;
    }
}
