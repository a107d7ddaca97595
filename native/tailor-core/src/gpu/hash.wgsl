// The generic half of a hash build (Eq. 1-3 by counting sort), shared by the collider and
// the particle tables: `scan` turns bucket sizes into starts (one workgroup: each thread sums
// a contiguous chunk of buckets, a workgroup scan offsets the chunks) and leaves the starts
// in `counts` as insertion cursors; `sort` (per bucket) orders a bucket's entries by
// (cell, primitive), which makes the table independent of the scatter's atomic order, and
// zeroes the bucket's count for the next build.

@group(0) @binding(2) var<uniform> table_info: TableInfo;
@group(0) @binding(3) var<storage, read_write> counts: array<atomic<u32>>;
@group(0) @binding(4) var<storage, read_write> table: array<u32>;

const SCAN: u32 = 256u;
var<workgroup> partial: array<u32, 256>;

@compute @workgroup_size(256)
fn scan(@builtin(local_invocation_index) li: u32) {
    let nb = table_info.n_buckets;
    let chunk = (nb + SCAN - 1u) / SCAN;
    let b0 = min(li * chunk, nb);
    let b1 = min(b0 + chunk, nb);
    var s = 0u;
    for (var b = b0; b < b1; b++) {
        s += atomicLoad(&counts[b]);
    }
    partial[li] = s;
    workgroupBarrier();
    // Hillis-Steele inclusive scan of the chunk sums.
    for (var off = 1u; off < SCAN; off <<= 1u) {
        var add = 0u;
        if (li >= off) {
            add = partial[li - off];
        }
        workgroupBarrier();
        partial[li] += add;
        workgroupBarrier();
    }
    var acc = partial[li] - s;
    for (var b = b0; b < b1; b++) {
        let c = atomicLoad(&counts[b]);
        table[b] = acc;
        atomicStore(&counts[b], acc);
        acc += c;
    }
    if (li == SCAN - 1u) {
        table[nb] = partial[SCAN - 1u];
    }
}

// Whether entry a sorts after entry b: cell coordinates (as i32), then the primitive.
fn entry_after(a: vec4<u32>, b: vec4<u32>) -> bool {
    let ax = bitcast<vec3<i32>>(a.xyz);
    let bx = bitcast<vec3<i32>>(b.xyz);
    if (ax.x != bx.x) {
        return ax.x > bx.x;
    }
    if (ax.y != bx.y) {
        return ax.y > bx.y;
    }
    if (ax.z != bx.z) {
        return ax.z > bx.z;
    }
    return a.w > b.w;
}

fn load_entry(base: u32, e: u32) -> vec4<u32> {
    let k = base + 4u * e;
    return vec4<u32>(table[k], table[k + 1u], table[k + 2u], table[k + 3u]);
}

fn store_entry(base: u32, e: u32, v: vec4<u32>) {
    let k = base + 4u * e;
    table[k] = v.x;
    table[k + 1u] = v.y;
    table[k + 2u] = v.z;
    table[k + 3u] = v.w;
}

@compute @workgroup_size(64)
fn sort(@builtin(global_invocation_id) gid: vec3<u32>) {
    let b = gid.x;
    let nb = table_info.n_buckets;
    if (b >= nb) {
        return;
    }
    let base = nb + 1u;
    let lo = table[b];
    let hi = table[b + 1u];
    // Insertion sort: buckets hold a few entries (table size twice the primitives).
    for (var i = lo + 1u; i < hi; i++) {
        let key = load_entry(base, i);
        var j = i;
        while (j > lo && entry_after(load_entry(base, j - 1u), key)) {
            store_entry(base, j, load_entry(base, j - 1u));
            j--;
        }
        store_entry(base, j, key);
    }
    atomicStore(&counts[b], 0u);
}
