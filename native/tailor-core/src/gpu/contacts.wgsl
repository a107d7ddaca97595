// Contact detection (port of `ContactSet::detect` and `detect_mesh_contacts`), once per
// iteration before the projections: the deepest analytic collider within the thickness gives
// the contact target p + n·(thickness − d); a particle with no analytic contact takes the
// deepest mesh-collider contact (particle-vs-cell test, `mesh_query.wgsl`). Either way the
// weight is CONTACT_WEIGHT_FACTOR·Dᵢ.

@group(0) @binding(2) var<storage, read> fdata: array<f32>;
@group(0) @binding(3) var<storage, read> x: array<vec4<f32>>;
@group(0) @binding(4) var<storage, read> particles: array<Particle>;
@group(0) @binding(5) var<storage, read> colliders: array<Collider>;
@group(0) @binding(6) var<storage, read_write> contacts: array<Contact>;

// `contacts::CONTACT_WEIGHT_FACTOR`.
const CONTACT_WEIGHT_FACTOR: f32 = 20.0;

@compute @workgroup_size(64)
fn detect(@builtin(global_invocation_id) gid: vec3<u32>) {
    // Early stop (`tolerance`): the substep has converged; the stage does nothing more.
    if (state.done != 0u) {
        return;
    }
    let i = gid.x;
    if (i >= params.n) {
        return;
    }
    var best = Contact(vec3<f32>(0.0), 0.0, vec3<f32>(0.0), NO_COLLIDER, vec3<f32>(0.0), 0u);
    if ((particles[i].flags & PARTICLE_PINNED) == 0u) {
        let p = x[i].xyz;
        var deepest = F32_MAX;
        for (var c = 0u; c < params.n_colliders; c++) {
            let dn = collider_distance(colliders[c], p);
            if (dn.w < params.thickness && dn.w < deepest) {
                deepest = dn.w;
                best = Contact(p + dn.xyz * (params.thickness - dn.w), CONTACT_WEIGHT_FACTOR * fdata[params.diag + i], dn.xyz, c, vec3<f32>(0.0), 0u);
            }
        }
        if (best.collider == NO_COLLIDER && params.n_meshes > 0u) {
            let d = deepest_mesh_contact(p, bitcast<i32>(idx[params.particle_levels + i]));
            if (d.hit.found != 0u) {
                best = Contact(d.hit.target_pos, CONTACT_WEIGHT_FACTOR * fdata[params.diag + i], d.hit.normal, MESH_CONTACT | d.collider, d.hit.bary, d.hit.tri);
            }
        }
    }
    contacts[i] = best;
}
