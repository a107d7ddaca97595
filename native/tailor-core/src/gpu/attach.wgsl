// Collider attachments (port of `Simulation::apply_collider_attachments`, `attach.rs`): a
// particle riding on its bound triangle of a mesh collider (a painted pin on the character).
// Per substep, after `mesh_hash.wgsl` `lerp` has this substep's collider positions: the target
// t = Σₖ bₖ·vₖ + F·o in the triangle's orthonormal frame F = [ê, n̂, n̂ × ê] (ê along the first
// edge, n̂ the face normal), and w·t onto the fixed right-hand side that `predict` wrote (the
// weight w is on the system's diagonal already). A triangle of no area keeps the last target.
// Each particle has at most one attachment, so the writes to `rhs` do not race.

struct Attachment {
    particle: u32,
    // Global vertex indices into the `mverts` sections.
    v0: u32,
    v1: u32,
    v2: u32,
    bary: vec3<f32>,
    weight: f32,
    local: vec3<f32>,
    _pad0: f32,
    last: vec3<f32>,
    _pad1: f32,
}

struct AttachInfo {
    n: u32,
    _pad0: u32,
    _pad1: u32,
    _pad2: u32,
}

@group(0) @binding(2) var<uniform> attach_info: AttachInfo;
@group(0) @binding(3) var<storage, read_write> attachments: array<Attachment>;
@group(0) @binding(4) var<storage, read> mverts: array<vec4<f32>>;
@group(0) @binding(6) var<storage, read_write> rhs: array<vec4<f32>>;

// `try_normalize` of glam: None (here: false) for a zero or non-finite length.
fn normalized(v: vec3<f32>, out: ptr<function, vec3<f32>>) -> bool {
    let l = length(v);
    if (!(l > 0.0) || l > 3.0e38) {
        return false;
    }
    *out = v * (1.0 / l);
    return true;
}

@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) gid: vec3<u32>) {
    let k = gid.x;
    if (k >= attach_info.n) {
        return;
    }
    let a = attachments[k];
    let cur = 2u * params.n_mesh_verts;
    let p0 = mverts[cur + a.v0].xyz;
    let p1 = mverts[cur + a.v1].xyz;
    let p2 = mverts[cur + a.v2].xyz;
    var t = a.last;
    var n: vec3<f32>;
    var e: vec3<f32>;
    if (normalized(cross(p1 - p0, p2 - p0), &n) && normalized(p1 - p0, &e)) {
        let q = p0 * a.bary.x + p1 * a.bary.y + p2 * a.bary.z;
        t = q + e * a.local.x + n * a.local.y + cross(n, e) * a.local.z;
        attachments[k].last = t;
    }
    let i = a.particle;
    rhs[i] = vec4<f32>(rhs[i].xyz + t * a.weight, 0.0);
}
