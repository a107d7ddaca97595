// Prediction stage (port of `Simulation::predict`): y = x + h·v + h²·g, g held by the ramp
// while seams close (`gravity_now`; pinned particles at
// their targets), initial guess x = y, fixed right-hand side M/h²·y + b_const; also starts the
// substep's Chebyshev sequence (prev = cur = y) and resets the iteration state.

@group(0) @binding(2) var<storage, read> particles: array<Particle>;
@group(0) @binding(3) var<storage, read_write> x: array<vec4<f32>>;
@group(0) @binding(4) var<storage, read> v: array<vec4<f32>>;
@group(0) @binding(5) var<storage, read_write> x_start: array<vec4<f32>>;
@group(0) @binding(6) var<storage, read_write> rhs: array<vec4<f32>>;
@group(0) @binding(7) var<storage, read_write> prev: array<vec4<f32>>;
@group(0) @binding(8) var<storage, read_write> cur: array<vec4<f32>>;

@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) gid: vec3<u32>) {
    let i = gid.x;
    if (i == 0u) {
        // `Chebyshev::begin_substep`, and the iteration counter.
        state.omega = 1.0;
        state.started = 0u;
        state.last_delta = F32_MAX;
        state.first_delta = F32_MAX;
        state.diverging = 0u;
        state.k = 0u;
        state.done = 0u;
        state.stop = 0u;
    }
    if (i >= params.n) {
        return;
    }
    let g = gravity_now();
    let p = particles[i];
    let xi = x[i].xyz;
    x_start[i] = vec4<f32>(xi, 0.0);
    var y: vec3<f32>;
    if ((p.flags & PARTICLE_PINNED) != 0u) {
        y = p.pin_target;
    } else {
        y = xi + v[i].xyz * params.h + g * (params.h * params.h);
    }
    let y4 = vec4<f32>(y, 0.0);
    x[i] = y4;
    prev[i] = y4;
    cur[i] = y4;
    rhs[i] = vec4<f32>(y * (p.mass * params.inv_h2) + p.b_const, 0.0);
}
