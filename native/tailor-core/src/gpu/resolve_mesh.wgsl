// End of substep, mesh colliders (port of `Simulation::resolve_mesh_penetrations`): a
// particle still behind a mesh collider goes to its target (so no substep ends inside), and
// every mesh contact of the substep gets Coulomb friction at the position level on its
// displacement relative to the touched triangle: with d the larger of (x − y)·n (how far the
// contact pushed it out of free flight) and the last iteration's contact force as a
// displacement, w·((p − x)·n)·h²/m (`contact_pushes`: the body pushing back against the
// cloth's tension too; not on sewn particles), the tangential part of (x − x₀ − v_c·h) is removed when under μs·d,
// else shortened by μk·d. A particle whose motion over the substep crossed a triangle front
// to back goes back out on that side (the crossing decides before the nearest surface), and
// a corrected particle whose path from the substep's start now crosses a surface stays where
// the substep began (`keep_corrections_in_front`). While seams close the push is 0 (their
// pull is an assembly force: what it presses onto the body slides). Runs before `finish`.

@group(0) @binding(2) var<storage, read_write> x: array<vec4<f32>>;
@group(0) @binding(3) var<storage, read> x_start: array<vec4<f32>>;
@group(0) @binding(4) var<storage, read> v: array<vec4<f32>>;
@group(0) @binding(5) var<storage, read_write> contacts: array<Contact>;
@group(0) @binding(6) var<storage, read> fdata: array<f32>;
@group(0) @binding(7) var<storage, read> particles: array<Particle>;

@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) gid: vec3<u32>) {
    let i = gid.x;
    if (i >= params.n || idx[params.pinned + i] != 0u) {
        return;
    }
    var ct = contacts[i];
    var p = x[i].xyz;
    let analytic = ct.weight > 0.0 && (ct.collider & MESH_CONTACT) == 0u;
    // The last iteration's contact force as a displacement (`contact_pushes`).
    var push = 0.0;
    if (!ramp_closing() && ct.weight > 0.0 && is_mesh(ct.collider) && (particles[i].flags & PARTICLE_SEWN) == 0u) {
        let behind = max(dot(ct.target_pos - p, ct.normal), 0.0);
        push = ct.weight * behind * params.h * params.h / particles[i].mass;
    }
    let level = bitcast<i32>(idx[params.particle_levels + i]);
    let xs = x_start[i].xyz;
    var d = deepest_mesh_crossing(xs, p, level);
    if (d.hit.found == 0u) {
        d = deepest_mesh_contact(p, level);
    }
    if (d.hit.found != 0u && !analytic) {
        p = d.hit.target_pos;
        ct.normal = d.hit.normal;
        ct.collider = MESH_CONTACT | d.collider;
        ct.tri = d.hit.tri;
        ct.bary = d.hit.bary;
    }
    if (is_mesh(ct.collider)) {
        let mi = meshes.m[ct.collider & ~MESH_CONTACT];
        let n = ct.normal;
        // The prediction y as `predict` computed it (contacts never involve pinned particles).
        let y = xs + v[i].xyz * params.h + gravity_now() * (params.h * params.h);
        let dn = max(dot(p - y, n), push);
        if (dn > 0.0) {
            var vc = vec3<f32>(0.0);
            if (mi.moving != 0u) {
                let gt = mi.tri_off + ct.tri;
                let vel = 3u * params.n_mesh_verts;
                vc = mverts[vel + mesh_vertex_index(gt, 0u)].xyz * ct.bary.x
                    + mverts[vel + mesh_vertex_index(gt, 1u)].xyz * ct.bary.y
                    + mverts[vel + mesh_vertex_index(gt, 2u)].xyz * ct.bary.z;
            }
            let rel = p - xs - vc * params.h;
            let rel_t = rel - n * dot(rel, n);
            let lt = length(rel_t);
            var mu = vec2<f32>(mi.static_friction, mi.kinetic_friction);
            if (params.has_friction != 0u) {
                mu = vec2<f32>(fdata[params.friction + 2u * i], fdata[params.friction + 2u * i + 1u]);
            }
            if (lt <= mu.x * dn) {
                p = p - rel_t;
            } else {
                p = p - rel_t * min(mu.y * dn / lt, 1.0);
            }
        }
    }
    if (is_mesh(ct.collider) && deepest_mesh_crossing(xs, p, level).hit.found != 0u) {
        p = xs;
    }
    x[i] = vec4<f32>(p, 0.0);
    contacts[i] = ct;
}
