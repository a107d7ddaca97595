// Damping stage (port of `Simulation::finish_substep` without colliders):
// v = (x − x_start)/h · exp(−c·h), with c the seam-closing ramp's damping before it advances.

@group(0) @binding(2) var<storage, read> x: array<vec4<f32>>;
@group(0) @binding(3) var<storage, read> x_start: array<vec4<f32>>;
@group(0) @binding(4) var<storage, read_write> v: array<vec4<f32>>;

@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) gid: vec3<u32>) {
    let i = gid.x;
    if (i >= params.n) {
        return;
    }
    let c = ramp_damping(state.phase, state.elapsed);
    let f = exp(-c * params.h);
    let vel = (x[i].xyz - x_start[i].xyz) * params.inv_h;
    v[i] = vec4<f32>(vel * f, 0.0);
}
