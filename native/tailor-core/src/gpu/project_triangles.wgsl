// Local step for triangles (exact port of `constraints/triangle.rs::rhs_contributions`):
// stretch projects each column of F to unit length (weighted along u and v: anisotropic
// fabrics), shear projects (c1, c2) onto the closest orthogonal pair; each triangle writes
// w·Aᵀp into its own three slots 3t..3t+3. Its data: g (6), stretch along u, shear, stretch
// along v.

@group(0) @binding(2) var<storage, read> idx: array<u32>;
@group(0) @binding(3) var<storage, read> fdata: array<f32>;
@group(0) @binding(4) var<storage, read> x: array<vec4<f32>>;
@group(0) @binding(5) var<storage, read_write> slots: array<vec4<f32>>;

fn unit_or_same(c: vec3<f32>) -> vec3<f32> {
    let l = length(c);
    if (l > 1e-12) {
        return c / l;
    }
    return c;
}

@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) gid: vec3<u32>) {
    // Early stop (`tolerance`): the substep has converged; the stage does nothing more.
    if (state.done != 0u) {
        return;
    }
    let t = gid.x;
    if (t >= params.n_tris) {
        return;
    }
    let vb = params.tri_verts + 3u * t;
    let x0 = x[idx[vb]].xyz;
    let x1 = x[idx[vb + 1u]].xyz;
    let x2 = x[idx[vb + 2u]].xyz;
    let fb = params.tri_data + 9u * t;
    let g00 = fdata[fb];
    let g01 = fdata[fb + 1u];
    let g10 = fdata[fb + 2u];
    let g11 = fdata[fb + 3u];
    let g20 = fdata[fb + 4u];
    let g21 = fdata[fb + 5u];
    let ws = fdata[fb + 6u];
    let wsh = fdata[fb + 7u];
    let wsv = fdata[fb + 8u];
    // Columns of F.
    let c0 = x0 * g00 + x1 * g10 + x2 * g20;
    let c1 = x0 * g01 + x1 * g11 + x2 * g21;
    // Stretch.
    let ps0 = unit_or_same(c0);
    let ps1 = unit_or_same(c1);
    // Shear: λ = 2d / (s + √(s² − 4d²)), the root with |λ| ≤ 1.
    let d = dot(c0, c1);
    let s = dot(c0, c0) + dot(c1, c1);
    let disc = max(s * s - 4.0 * d * d, 0.0);
    let lambda = 2.0 * d / max(s + sqrt(disc), 1e-30);
    let denom = 1.0 - lambda * lambda;
    var ph0 = c0;
    var ph1 = c1;
    // Parallel columns of equal length: every rotation is as close; keep the state. Written as
    // the CPU's test negated (not `>=`) so that a NaN takes the same branch where NaNs are kept.
    if (!(denom < 1e-6)) {
        let inv = 1.0 / denom;
        ph0 = (c0 - c1 * lambda) * inv;
        ph1 = (c1 - c0 * lambda) * inv;
    }
    let q0 = ps0 * ws + ph0 * wsh;
    let q1 = ps1 * wsv + ph1 * wsh;
    let sb = 3u * t;
    slots[sb] = vec4<f32>(q0 * g00 + q1 * g01, 0.0);
    slots[sb + 1u] = vec4<f32>(q0 * g10 + q1 * g11, 0.0);
    slots[sb + 2u] = vec4<f32>(q0 * g20 + q1 * g21, 0.0);
}
