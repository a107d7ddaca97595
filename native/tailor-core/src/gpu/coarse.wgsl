// The two-level global step's coarse correction (port of `solver/stages/coarse.rs`), after each
// iteration's sweep and extrapolation:
//
// * `residual` (a particle each): rᵢ = (tᵢ − xᵢ)·Dᵢ with tᵢ the row's solve as `gauss_seidel`
//   computes it (contacts in the row), Dᵢ its diagonal; the contact weight rides in `.w`;
// * `restrict_residual` (an aggregate each): r_c = Σ rᵢ over its members in ascending order (the CPU's
//   order), and the coarse diagonal: the Galerkin diagonal without contacts plus the members'
//   contact weights;
// * `solve` (one workgroup): A_c e = r_c by conjugate gradients preconditioned by the diagonal,
//   the three coordinates in lockstep, `params.coarse_iterations` at most, stopping (as the
//   CPU's loop does) once rᵀz is 1e-10 of its start in all three;
// * `prolong` (a particle each): x ← x + e of its aggregate; `prolong_history` also makes the
//   corrected iterate Chebyshev's current one (`cur`), as the CPU's correction of `x` after the
//   swap makes it the next iteration's previous iterate.
//
// The coarse vectors share `cw`, `params.n_coarse` (m) entries a section: r at 0, e at m, p at
// 2m, q at 3m, and (diagonal, its inverse) at 4m.

const NONE: u32 = 0xffffffffu;
const CG: u32 = 256u;

@group(0) @binding(2) var<storage, read> idx: array<u32>;
@group(0) @binding(3) var<storage, read> fdata: array<f32>;
@group(0) @binding(4) var<storage, read_write> x: array<vec4<f32>>;
@group(0) @binding(5) var<storage, read> rhs: array<vec4<f32>>;
@group(0) @binding(6) var<storage, read> slots: array<vec4<f32>>;
@group(0) @binding(7) var<storage, read> contacts: array<Contact>;
@group(0) @binding(8) var<storage, read_write> cres: array<vec4<f32>>;
@group(0) @binding(9) var<storage, read_write> cw: array<vec4<f32>>;
@group(0) @binding(10) var<storage, read_write> cur: array<vec4<f32>>;

var<workgroup> red: array<vec4<f32>, 256>;

@compute @workgroup_size(64)
fn residual(@builtin(global_invocation_id) gid: vec3<u32>) {
    if (state.done != 0u) {
        return;
    }
    let i = gid.x;
    if (i >= params.n) {
        return;
    }
    if (idx[params.coarse_agg + i] == NONE) {
        cres[i] = vec4<f32>(0.0);
        return;
    }
    let row = row_of(i);
    let d = row.diagonal;
    cres[i] = vec4<f32>((row.sum / d - x[i].xyz) * d, row.contact_weight);
}

@compute @workgroup_size(64)
fn restrict_residual(@builtin(global_invocation_id) gid: vec3<u32>) {
    if (state.done != 0u) {
        return;
    }
    let a = gid.x;
    let m = params.n_coarse;
    if (a >= m) {
        return;
    }
    var r = vec3<f32>(0.0);
    var d = fdata[params.coarse_diag0 + a];
    let k0 = idx[params.coarse_member_off + a];
    let k1 = idx[params.coarse_member_off + a + 1u];
    for (var k = k0; k < k1; k++) {
        let q = cres[idx[params.coarse_members + k]];
        r += q.xyz;
        d += q.w;
    }
    cw[a] = vec4<f32>(r, 0.0);
    cw[4u * m + a] = vec4<f32>(d, 0.0, 0.0, 0.0);
}

// The workgroup's sum of `v` (a fixed tree: deterministic), the same in every invocation.
fn workgroup_sum(li: u32, v: vec3<f32>) -> vec3<f32> {
    red[li] = vec4<f32>(v, 0.0);
    workgroupBarrier();
    for (var s = CG / 2u; s > 0u; s >>= 1u) {
        if (li < s) {
            red[li] += red[li + s];
        }
        workgroupBarrier();
    }
    let total = red[0].xyz;
    workgroupBarrier();
    return total;
}

@compute @workgroup_size(256)
fn solve(@builtin(local_invocation_index) li: u32) {
    if (state.done != 0u) {
        return;
    }
    let m = params.n_coarse;
    // e = 0, z = D⁻¹r, p = z.
    var part = vec3<f32>(0.0);
    for (var a = li; a < m; a += CG) {
        let d = cw[4u * m + a].x;
        var inv = 0.0;
        if (d > 0.0) {
            inv = 1.0 / d;
        }
        cw[4u * m + a].y = inv;
        let r = cw[a].xyz;
        let p = r * inv;
        cw[m + a] = vec4<f32>(0.0);
        cw[2u * m + a] = vec4<f32>(p, 0.0);
        part += r * p;
    }
    var rz = workgroup_sum(li, part);
    let r0 = rz;
    // Every invocation runs every pass (the barriers need it); a converged solve stops changing.
    var live = true;
    for (var it = 0u; it < params.coarse_iterations; it++) {
        if (all(rz <= r0 * 1e-10)) {
            live = false;
        }
        storageBarrier();
        // q = A_c p (`CoarseLevel::apply`'s order), and pᵀq.
        part = vec3<f32>(0.0);
        if (live) {
            for (var a = li; a < m; a += CG) {
                let p = cw[2u * m + a].xyz;
                var s = p * cw[4u * m + a].x;
                let k0 = idx[params.coarse_off + a];
                let k1 = idx[params.coarse_off + a + 1u];
                for (var k = k0; k < k1; k++) {
                    s += cw[2u * m + idx[params.coarse_cols + k]].xyz * fdata[params.coarse_vals + k];
                }
                cw[3u * m + a] = vec4<f32>(s, 0.0);
                part += p * s;
            }
        }
        let pq = workgroup_sum(li, part);
        let alpha = select(vec3<f32>(0.0), rz / pq, pq > vec3<f32>(0.0));
        part = vec3<f32>(0.0);
        if (live) {
            for (var a = li; a < m; a += CG) {
                let p = cw[2u * m + a].xyz;
                cw[m + a] = vec4<f32>(cw[m + a].xyz + p * alpha, 0.0);
                let r = cw[a].xyz - cw[3u * m + a].xyz * alpha;
                cw[a] = vec4<f32>(r, 0.0);
                part += r * r * cw[4u * m + a].y;
            }
        }
        let rz_new = workgroup_sum(li, part);
        let beta = select(vec3<f32>(0.0), rz_new / rz, rz > vec3<f32>(0.0));
        if (live) {
            for (var a = li; a < m; a += CG) {
                let p = cw[a].xyz * cw[4u * m + a].y + cw[2u * m + a].xyz * beta;
                cw[2u * m + a] = vec4<f32>(p, 0.0);
            }
            rz = rz_new;
        }
    }
}

// x ← x + e of the particle's aggregate; the new x returned (unchanged for a pinned particle).
fn add_correction(i: u32) -> vec4<f32> {
    let a = idx[params.coarse_agg + i];
    if (a == NONE) {
        return x[i];
    }
    let xi = vec4<f32>(x[i].xyz + cw[params.n_coarse + a].xyz, 0.0);
    x[i] = xi;
    return xi;
}

@compute @workgroup_size(64)
fn prolong(@builtin(global_invocation_id) gid: vec3<u32>) {
    if (state.done != 0u || gid.x >= params.n) {
        return;
    }
    add_correction(gid.x);
}

@compute @workgroup_size(64)
fn prolong_history(@builtin(global_invocation_id) gid: vec3<u32>) {
    if (state.done != 0u || gid.x >= params.n) {
        return;
    }
    cur[gid.x] = add_correction(gid.x);
}
