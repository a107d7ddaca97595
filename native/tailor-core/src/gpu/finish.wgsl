// Damping stage (port of `Simulation::finish_substep`, after `resolve_mesh`): penetrations of
// analytic colliders left after the iterations are pushed out, v = (x − x_start)/h, Coulomb friction for particles in contact
// (the normal impulse the larger of the change from free flight and the last iteration's
// contact force, `contact_pushes`),
// then air damping exp(−c·h) with c the seam-closing ramp's damping before it advances.

@group(0) @binding(2) var<storage, read_write> x: array<vec4<f32>>;
@group(0) @binding(3) var<storage, read> x_start: array<vec4<f32>>;
@group(0) @binding(4) var<storage, read_write> v: array<vec4<f32>>;
@group(0) @binding(5) var<storage, read> contacts: array<Contact>;
@group(0) @binding(6) var<storage, read> colliders: array<Collider>;
@group(0) @binding(7) var<storage, read> particles: array<Particle>;

// The workgroup's top speed at the frame's last substep, before one atomic per workgroup on the
// step state (one per particle on a single address would serialise a million-particle frame).
var<workgroup> wg_speed: atomic<u32>;

// Port of `contacts::coulomb`.
fn coulomb(v: vec3<f32>, n: vec3<f32>, dvn: f32, mu_s: f32, mu_k: f32) -> vec3<f32> {
    let vn = n * dot(v, n);
    let vt = v - vn;
    let lt = length(vt);
    if (lt <= mu_s * dvn) {
        return vn;
    }
    return vn + vt * max(1.0 - mu_k * dvn / lt, 0.0);
}

@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(local_invocation_index) li: u32) {
    // Barriers in uniform control flow; only the frame's last substep reports the speed.
    if (li == 0u) {
        atomicStore(&wg_speed, 0u);
    }
    workgroupBarrier();
    // For the sleep test: the fastest speed at the end of the frame (non-negative floats order
    // as their bits).
    atomicMax(&wg_speed, bitcast<u32>(finish_particle(gid.x)));
    workgroupBarrier();
    if (li == 0u && state.substep + 1u == params.substeps) {
        atomicMax(&state.max_speed_bits, atomicLoad(&wg_speed));
    }
}

// One particle's damping stage; returns its speed afterwards (0 past the last particle).
fn finish_particle(i: u32) -> f32 {
    if (i >= params.n) {
        return 0.0;
    }
    var p = x[i].xyz;
    let ct = contacts[i];
    // The last iteration's contact force as a displacement (`contact_pushes`), before the
    // remaining penetrations are pushed out.
    var push = 0.0;
    // Zero while seams close (their pull is an assembly force: what it presses on slides).
    if (!ramp_closing() && ct.weight > 0.0 && is_analytic(ct.collider) && (particles[i].flags & PARTICLE_SEWN) == 0u) {
        push = ct.weight * max(dot(ct.target_pos - p, ct.normal), 0.0) * params.h * params.h / particles[i].mass;
    }
    if (params.n_colliders > 0u && (particles[i].flags & PARTICLE_PINNED) == 0u) {
        // `contacts::resolve_penetrations`, colliders in order.
        var touched = false;
        for (var c = 0u; c < params.n_colliders; c++) {
            let dn = collider_distance(colliders[c], p);
            if (dn.w < params.thickness) {
                p += dn.xyz * (params.thickness - dn.w);
                touched = true;
            }
        }
        if (touched) {
            x[i] = vec4<f32>(p, 0.0);
        }
    }
    let xs = x_start[i].xyz;
    var vel = (p - xs) * params.inv_h;
    // Mesh contacts had their friction in `resolve_mesh.wgsl`.
    if (is_analytic(ct.collider)) {
        // The prediction y as `predict` computed it (contacts never involve pinned particles).
        let y = xs + v[i].xyz * params.h + gravity_now() * (params.h * params.h);
        let v_pred = (y - xs) * params.inv_h;
        let dvn = max(max(dot(vel - v_pred, ct.normal), push * params.inv_h), 0.0);
        let col = colliders[ct.collider];
        vel = coulomb(vel, ct.normal, dvn, col.static_friction, col.kinetic_friction);
    }
    let c = ramp_damping(state.phase, state.elapsed);
    let f = exp(-c * params.h);
    v[i] = vec4<f32>(vel * f, 0.0);
    return length(vel * f);
}
