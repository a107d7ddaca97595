// Seams closing on their schedule (port of `Simulation::close_seams`), one workgroup, first in
// every substep while some pair has schedule left: what is left of each pair's schedule
// shrinks, the widest pair's (by its gap when sewn) by `closing_speed·h`, every other's by its
// share, so that all run out together; a pair's rest length is what is left, never above its
// current gap. The rest length goes into the pair's curved stencil (`project_stencils`), and
// `state.closing` says whether any schedule is left (the ramp's `scheduled`).
//
// `closing` holds one vec4 per seam pair: (gap when sewn, schedule left, the pair's curved
// stencil index as u32 bits or 0xffffffff, rest length). `fdata` is written here only.

@group(0) @binding(2) var<storage, read> idx: array<u32>;
@group(0) @binding(3) var<storage, read_write> fdata: array<f32>;
@group(0) @binding(4) var<storage, read> x: array<vec4<f32>>;
@group(0) @binding(5) var<storage, read_write> closing: array<vec4<f32>>;

const REDUCE: u32 = 256u;
// f32::MIN_POSITIVE, the CPU's start of the widest-gap fold.
const F32_MIN_POSITIVE: f32 = 1.17549435e-38;
var<workgroup> widest: array<f32, 256>;
var<workgroup> open: array<u32, 256>;

@compute @workgroup_size(256)
fn main(@builtin(local_invocation_index) li: u32) {
    // Every thread reads the flag before anyone writes it (thread 0 writes after the barriers).
    let scheduled = state.closing != 0u;
    var w = F32_MIN_POSITIVE;
    if (scheduled) {
        for (var s = li; s < params.n_seam_pairs; s += REDUCE) {
            let c = closing[s];
            if (c.y > 0.0) {
                w = max(w, c.x);
            }
        }
    }
    widest[li] = w;
    workgroupBarrier();
    for (var k = REDUCE / 2u; k > 0u; k >>= 1u) {
        if (li < k) {
            widest[li] = max(widest[li], widest[li + k]);
        }
        workgroupBarrier();
    }
    let wd = widest[0];
    var o = 0u;
    if (scheduled) {
        for (var s = li; s < params.n_seam_pairs; s += REDUCE) {
            var c = closing[s];
            if (!(c.y > 0.0)) {
                continue;
            }
            // Without the ramp the speed is infinite: the schedule runs out at once.
            var left = 0.0;
            if (params.ramp_enabled != 0u) {
                left = max(c.y - params.closing_speed * params.h * (c.x / wd), 0.0);
            }
            let t0 = idx[params.seam_off + s];
            let t1 = idx[params.seam_off + s + 1u];
            var v = vec3<f32>(0.0);
            for (var t = t0; t < t1; t++) {
                v += x[idx[params.seam_verts + t]].xyz * fdata[params.seam_coefs + t];
            }
            let rest = min(left, length(v));
            c.y = left;
            c.w = rest;
            closing[s] = c;
            let k = bitcast<u32>(c.z);
            if (k != 0xffffffffu) {
                fdata[params.curved_wr + 2u * k + 1u] = rest;
            }
            o += select(0u, 1u, left > 0.0);
        }
    }
    open[li] = o;
    workgroupBarrier();
    for (var k = REDUCE / 2u; k > 0u; k >>= 1u) {
        if (li < k) {
            open[li] += open[li + k];
        }
        workgroupBarrier();
    }
    if (li == 0u) {
        state.closing = select(0u, 1u, open[0] > 0u);
    }
}
