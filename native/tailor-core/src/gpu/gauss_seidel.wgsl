// Global step, one colour (port of `GlobalSystem::row`): xᵢ = (rhs_fixedᵢ + Σ slotsᵢ − Σⱼ Lᵢⱼxⱼ)/Dᵢ
// for the particles of this colour. No two particles of a colour share a matrix entry, so the
// invocations are independent; the dispatches of successive colours are ordered by wgpu.
// Contacts add their weight to the row (a penalty towards the contact target).
// Writes each particle's squared update and D²-weighted squared update (for Chebyshev's
// growth check and the residual).

struct ColourRange {
    start: u32,
    count: u32,
    _pad0: u32,
    _pad1: u32,
}

@group(0) @binding(2) var<uniform> colour: ColourRange;
@group(0) @binding(3) var<storage, read> idx: array<u32>;
@group(0) @binding(4) var<storage, read> fdata: array<f32>;
@group(0) @binding(5) var<storage, read_write> x: array<vec4<f32>>;
@group(0) @binding(6) var<storage, read> rhs: array<vec4<f32>>;
@group(0) @binding(7) var<storage, read> slots: array<vec4<f32>>;
@group(0) @binding(8) var<storage, read_write> norms: array<vec2<f32>>;
@group(0) @binding(9) var<storage, read> contacts: array<Contact>;

@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) gid: vec3<u32>) {
    // Early stop (`tolerance`): the substep has converged; the stage does nothing more.
    if (state.done != 0u) {
        return;
    }
    if (gid.x >= colour.count) {
        return;
    }
    let i = idx[params.order + colour.start + gid.x];
    let row = row_of(i);
    let d = row.diagonal;
    let new_x = row.sum / d;
    let du = new_x - x[i].xyz;
    x[i] = vec4<f32>(new_x, 0.0);
    let u2 = dot(du, du);
    norms[i] = vec2<f32>(u2, u2 * d * d);
}
