// Local step for curved stencils (port of the tail of `local.rs::project_all` and
// `constraints/stencil.rs::project`): v = Σ cₖ x_{iₖ}, p = r·v/‖v‖ (0 when ‖v‖ is tiny),
// and each term k writes w·cₖ·p into its own slot. Flat stencils (r = 0) have p = 0 and are
// not in this list: they live entirely in the matrix.

@group(0) @binding(2) var<storage, read> idx: array<u32>;
@group(0) @binding(3) var<storage, read> fdata: array<f32>;
@group(0) @binding(4) var<storage, read> x: array<vec4<f32>>;
@group(0) @binding(5) var<storage, read_write> slots: array<vec4<f32>>;

@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) gid: vec3<u32>) {
    // Early stop (`tolerance`): the substep has converged; the stage does nothing more.
    if (state.done != 0u) {
        return;
    }
    let c = gid.x;
    if (c >= params.n_curved) {
        return;
    }
    let t0 = idx[params.curved_off + c];
    let t1 = idx[params.curved_off + c + 1u];
    var v = vec3<f32>(0.0);
    for (var t = t0; t < t1; t++) {
        v += x[idx[params.curved_verts + t]].xyz * fdata[params.curved_coefs + t];
    }
    let weight = fdata[params.curved_wr + 2u * c];
    let rest = fdata[params.curved_wr + 2u * c + 1u];
    var p = vec3<f32>(0.0);
    let l = length(v);
    if (l > 1e-12) {
        p = v * (rest / l);
    }
    p = p * weight;
    let base = 3u * params.n_tris;
    for (var t = t0; t < t1; t++) {
        slots[base + t] = vec4<f32>(p * fdata[params.curved_coefs + t], 0.0);
    }
}
