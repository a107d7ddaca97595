// The generic half of a hash build (Eq. 1-3 by counting sort), shared by the collider and
// the particle tables. The scan turns bucket sizes into starts in three passes over blocks of
// BLOCK buckets, so that every pass is spread over the GPU (one workgroup scanning a
// million-particle table serially cost more than the rest of the iteration): `scan_blocks`
// sums each block's buckets, `scan_sums` (one workgroup) turns the block sums into the
// blocks' starts and writes the table's total, `scan_apply` scans each block from its start
// and leaves the starts in `counts` as insertion cursors. `sort` (per bucket) orders a
// bucket's entries by (cell, primitive), which makes the table independent of the scatter's
// atomic order, and zeroes the bucket's count for the next build.

@group(0) @binding(2) var<uniform> table_info: TableInfo;
@group(0) @binding(3) var<storage, read_write> counts: array<atomic<u32>>;
@group(0) @binding(4) var<storage, read_write> table: array<u32>;
@group(0) @binding(5) var<storage, read_write> block_sums: array<u32>;

const SCAN: u32 = 256u;
// Buckets per thread in a block: four neighbours, so a warp reads 512 contiguous bytes.
const PER_THREAD: u32 = 4u;
const BLOCK: u32 = 1024u;
var<workgroup> partial: array<u32, 256>;

// The inclusive scan of `v` over the workgroup's threads (Hillis-Steele); every thread calls it.
fn workgroup_scan(li: u32, v: u32) -> u32 {
    partial[li] = v;
    workgroupBarrier();
    for (var off = 1u; off < SCAN; off <<= 1u) {
        var add = 0u;
        if (li >= off) {
            add = partial[li - off];
        }
        workgroupBarrier();
        partial[li] += add;
        workgroupBarrier();
    }
    return partial[li];
}

// The sum of this thread's PER_THREAD buckets of block `block`.
fn thread_sum(block: u32, li: u32, nb: u32) -> u32 {
    let b0 = block * BLOCK + li * PER_THREAD;
    var s = 0u;
    for (var j = 0u; j < PER_THREAD; j++) {
        if (b0 + j < nb) {
            s += atomicLoad(&counts[b0 + j]);
        }
    }
    return s;
}

@compute @workgroup_size(256)
fn scan_blocks(@builtin(workgroup_id) wg: vec3<u32>, @builtin(local_invocation_index) li: u32) {
    let incl = workgroup_scan(li, thread_sum(wg.x, li, table_info.n_buckets));
    if (li == SCAN - 1u) {
        block_sums[wg.x] = incl;
    }
}

@compute @workgroup_size(256)
fn scan_sums(@builtin(local_invocation_index) li: u32) {
    let nb = table_info.n_buckets;
    let blocks = (nb + BLOCK - 1u) / BLOCK;
    let chunk = (blocks + SCAN - 1u) / SCAN;
    let k0 = min(li * chunk, blocks);
    let k1 = min(k0 + chunk, blocks);
    var s = 0u;
    for (var k = k0; k < k1; k++) {
        s += block_sums[k];
    }
    let incl = workgroup_scan(li, s);
    var acc = incl - s;
    for (var k = k0; k < k1; k++) {
        let c = block_sums[k];
        block_sums[k] = acc;
        acc += c;
    }
    if (li == SCAN - 1u) {
        table[nb] = incl;
    }
}

@compute @workgroup_size(256)
fn scan_apply(@builtin(workgroup_id) wg: vec3<u32>, @builtin(local_invocation_index) li: u32) {
    let nb = table_info.n_buckets;
    let s = thread_sum(wg.x, li, nb);
    let incl = workgroup_scan(li, s);
    var acc = block_sums[wg.x] + incl - s;
    let b0 = wg.x * BLOCK + li * PER_THREAD;
    for (var j = 0u; j < PER_THREAD; j++) {
        let b = b0 + j;
        if (b < nb) {
            let c = atomicLoad(&counts[b]);
            table[b] = acc;
            atomicStore(&counts[b], acc);
            acc += c;
        }
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
