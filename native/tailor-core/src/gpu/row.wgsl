// One row of the global step's system (port of `GlobalSystem::row`), shared by the sweep
// (`gauss_seidel.wgsl`) and the two-level step's residual (`coarse.wgsl`), each of which declares
// `idx`, `fdata`, `x`, `rhs`, `slots` and `contacts`:
// (rhs_fixedᵢ + Σ slotsᵢ − Σⱼ Lᵢⱼxⱼ + wᵢ·tᵢ, Dᵢ + wᵢ) in the CPU's order, and the contact weight wᵢ
// (0 without a contact): the row's solve is the first over the second.
struct Row {
    sum: vec3<f32>,
    diagonal: f32,
    contact_weight: f32,
}

fn row_of(i: u32) -> Row {
    var r = rhs[i].xyz;
    let s0 = idx[params.slot_off + i];
    let s1 = idx[params.slot_off + i + 1u];
    for (var s = s0; s < s1; s++) {
        r += slots[idx[params.slot_idx + s]].xyz;
    }
    let k0 = idx[params.mat_off + i];
    let k1 = idx[params.mat_off + i + 1u];
    for (var k = k0; k < k1; k++) {
        r -= x[idx[params.mat_cols + k]].xyz * fdata[params.mat_vals + k];
    }
    var d = fdata[params.diag + i];
    let c = contacts[i];
    var w = 0.0;
    if (c.weight > 0.0) {
        r += c.target_pos * c.weight;
        d += c.weight;
        w = c.weight;
    }
    return Row(r, d, w);
}
