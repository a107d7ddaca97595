// Seam gaps, the contact counts, the substep counter, and the seam-closing ramp (port of `Simulation::seam_gaps` and `Ramp::advance`),
// one workgroup: the largest sewn-pair gap and the fraction under the threshold decide the
// ramp's next phase, so no per-substep readback is needed.

@group(0) @binding(2) var<storage, read> idx: array<u32>;
@group(0) @binding(3) var<storage, read> fdata: array<f32>;
@group(0) @binding(4) var<storage, read> x: array<vec4<f32>>;
@group(0) @binding(5) var<storage, read> contacts: array<Contact>;
@group(0) @binding(6) var<storage, read> sdelta: array<vec4<f32>>;

const REDUCE: u32 = 256u;
var<workgroup> gap_max: array<f32, 256>;
var<workgroup> closed: array<u32, 256>;
var<workgroup> touching: array<u32, 256>;
var<workgroup> meshed: array<u32, 256>;
var<workgroup> pairs: array<u32, 256>;

@compute @workgroup_size(256)
fn main(@builtin(local_invocation_index) li: u32) {
    var m = 0.0;
    var c = 0u;
    for (var s = li; s < params.n_seam_pairs; s += REDUCE) {
        let t0 = idx[params.seam_off + s];
        let t1 = idx[params.seam_off + s + 1u];
        var v = vec3<f32>(0.0);
        for (var t = t0; t < t1; t++) {
            v += x[idx[params.seam_verts + t]].xyz * fdata[params.seam_coefs + t];
        }
        let g = length(v);
        m = max(m, g);
        c += select(0u, 1u, g < params.gap_threshold);
    }
    var tc = 0u;
    var mc = 0u;
    var pc = 0u;
    for (var i = li; i < params.n; i += REDUCE) {
        let ct = contacts[i];
        tc += select(0u, 1u, ct.weight > 0.0);
        mc += select(0u, 1u, is_mesh(ct.collider));
        if (params.self_enabled != 0u) {
            pc += u32(sdelta[i].w);
        }
    }
    gap_max[li] = m;
    closed[li] = c;
    touching[li] = tc;
    meshed[li] = mc;
    pairs[li] = pc;
    workgroupBarrier();
    for (var s = REDUCE / 2u; s > 0u; s >>= 1u) {
        if (li < s) {
            gap_max[li] = max(gap_max[li], gap_max[li + s]);
            closed[li] += closed[li + s];
            touching[li] += touching[li + s];
            meshed[li] += meshed[li + s];
            pairs[li] += pairs[li + s];
        }
        workgroupBarrier();
    }
    if (li != 0u) {
        return;
    }
    var frac = 1.0;
    if (params.n_seam_pairs > 0u) {
        frac = f32(closed[0]) / f32(params.n_seam_pairs);
    }
    state.gap_max = gap_max[0];
    state.closed_fraction = frac;
    state.contacts = touching[0];
    state.mesh_contacts = meshed[0];
    // Each overlapping pair was counted by both of its particles.
    state.self_pairs = pairs[0] / 2u;
    state.substep = (state.substep + 1u) % params.substeps;
    // `Ramp::advance`: released when the seams have met (the fraction closed and the widest
    // gap), or, once every pair's schedule has run out, when the widest gap has stopped
    // shrinking (`Ramp::stalled`).
    let h = params.h;
    let widest = gap_max[0];
    let met = frac >= params.closed_fraction && widest <= params.release_gap;
    var stalled = false;
    if (state.phase == PHASE_CLOSING && state.closing == 0u) {
        var best = widest;
        var since = 0.0;
        if (state.stall_on != 0u && widest >= STALL_SHRINK * state.stall_best) {
            best = state.stall_best;
            since = state.stall_since + h;
        }
        state.stall_on = 1u;
        state.stall_best = best;
        state.stall_since = since;
        stalled = since >= STALL_TIME;
    }
    if (params.has_seams == 0u) {
        state.phase = PHASE_DONE;
    } else if (state.phase == PHASE_CLOSING) {
        if (met || stalled) {
            state.phase = PHASE_RELEASING;
            state.elapsed = 0.0;
        }
    } else if (state.phase == PHASE_RELEASING) {
        if (state.elapsed + h >= params.release_time) {
            state.phase = PHASE_DONE;
        } else {
            state.elapsed = state.elapsed + h;
        }
    }
}

// `damping::STALL_TIME` and `damping::STALL_SHRINK` (`ramp.rs` checks they agree).
const STALL_TIME: f32 = 0.5;
const STALL_SHRINK: f32 = 0.95;
