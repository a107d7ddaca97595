// Chebyshev acceleration on the GPU (port of `solver/stages/chebyshev.rs`, ρ measured on the CPU).
// The sweep's squared updates are summed in two passes: `reduce_partial` (up to REDUCE
// workgroups, grid-stride) leaves one partial sum per workgroup, and `reduce_omega` (one
// workgroup) sums those, applies the growth check and the ω recurrence, and records the
// relative residual; `extrapolate` then applies x ← ω(x − prev) + prev and shifts the history
// (prev ← cur, cur ← x). One workgroup reading every particle was latency-bound: at a million
// particles it cost milliseconds an iteration.

@group(0) @binding(2) var<storage, read> norms: array<vec2<f32>>;
@group(0) @binding(3) var<storage, read_write> x: array<vec4<f32>>;
@group(0) @binding(4) var<storage, read_write> prev: array<vec4<f32>>;
@group(0) @binding(5) var<storage, read_write> cur: array<vec4<f32>>;
// One partial (update², residual²) sum per `reduce_partial` workgroup; zero past the last.
@group(0) @binding(6) var<storage, read_write> partials: array<vec2<f32>, 256>;

const REDUCE: u32 = 256u;
// `chebyshev.rs::RUNAWAY`.
const RUNAWAY: f32 = 10.0;
var<workgroup> sum_u: array<f32, 256>;
var<workgroup> sum_r: array<f32, 256>;

// The workgroup's sums of (a, b) left in sum_u[0], sum_r[0] (a fixed tree: deterministic).
fn workgroup_sum(li: u32, a: f32, b: f32) {
    sum_u[li] = a;
    sum_r[li] = b;
    workgroupBarrier();
    for (var s = REDUCE / 2u; s > 0u; s >>= 1u) {
        if (li < s) {
            sum_u[li] += sum_u[li + s];
            sum_r[li] += sum_r[li + s];
        }
        workgroupBarrier();
    }
}

@compute @workgroup_size(256)
fn reduce_partial(
    @builtin(workgroup_id) wg: vec3<u32>,
    @builtin(num_workgroups) groups: vec3<u32>,
    @builtin(local_invocation_index) li: u32,
) {
    if (state.done != 0u) {
        return;
    }
    var a = 0.0;
    var b = 0.0;
    for (var i = wg.x * REDUCE + li; i < params.n; i += groups.x * REDUCE) {
        let q = norms[i];
        a += q.x;
        b += q.y;
    }
    workgroup_sum(li, a, b);
    if (li == 0u) {
        partials[wg.x] = vec2<f32>(sum_u[0], sum_r[0]);
    }
    // Slots past the last workgroup read zero (a smaller upload may follow a larger one).
    if (wg.x == 0u && groups.x + li < REDUCE) {
        partials[groups.x + li] = vec2<f32>(0.0);
    }
}

@compute @workgroup_size(256)
fn reduce_omega(@builtin(local_invocation_index) li: u32) {
    if (state.done != 0u) {
        return;
    }
    let q = partials[li];
    workgroup_sum(li, q.x, q.y);
    if (li != 0u) {
        return;
    }
    let delta = sqrt(sum_u[0]);
    let res = sqrt(sum_r[0]);
    let k = state.k;
    if (k == 0u) {
        state.r0 = max(res, 1e-30);
    }
    state.residual = res / state.r0;
    // The CPU's early stop (`Simulation::iterate`): relative to the larger of the first
    // residual and the cloth's weight; this iteration's extrapolation still runs.
    if (state.tolerance > 0.0 && k > 0u && res < state.tolerance * max(state.r0, state.weight_norm)) {
        state.stop = 1u;
    }
    state.iterations_run += 1u;
    // `Chebyshev::omega`: restart when the update norm grew; plain sweeps to the substep's end
    // once an update outgrew the first sweep's RUNAWAY times; the last iteration is plain.
    let grew = state.started != 0u && delta > state.last_delta;
    state.last_delta = delta;
    if (k == 0u) {
        state.first_delta = delta;
    } else if (delta > RUNAWAY * state.first_delta) {
        state.diverging = 1u;
    }
    let rho = params.rho;
    if (k < params.delay || rho <= 0.0 || grew || state.diverging != 0u || k + 1u >= params.iterations) {
        state.started = 0u;
        state.omega = 1.0;
    } else {
        let rho2 = rho * rho;
        if (state.started != 0u) {
            state.omega = 4.0 / (4.0 - rho2 * state.omega);
        } else {
            state.omega = 2.0 / (2.0 - rho2);
        }
        state.started = 1u;
    }
    state.k = k + 1u;
}

@compute @workgroup_size(64)
fn extrapolate(@builtin(global_invocation_id) gid: vec3<u32>) {
    // Early stop (`tolerance`): the substep has converged; the stage does nothing more.
    if (state.done != 0u) {
        return;
    }
    let i = gid.x;
    if (i >= params.n) {
        return;
    }
    let w = state.omega;
    var xi = x[i];
    let p = prev[i];
    // The CPU skips ω = 1 entirely; (x − p) + p is not always x in floating point.
    if (w != 1.0) {
        xi = vec4<f32>(w * (xi.xyz - p.xyz) + p.xyz, 0.0);
        x[i] = xi;
    }
    prev[i] = cur[i];
    cur[i] = xi;
}

// First in each iteration when the early stop is on: a converged substep stops here.
@compute @workgroup_size(1)
fn gate() {
    if (state.stop != 0u) {
        state.done = 1u;
    }
}
