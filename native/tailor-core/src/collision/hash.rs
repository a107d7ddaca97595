//! The spatial hash of Nylén et al. 2020, Eq. 1-3 (after Teschner et al. 2003).
//!
//! Space is cut into cubes of side `l`; a primitive is filed under every cell it is inserted
//! in. For a cell with integer coordinates
//!
//! ```text
//! i = (floor(x / l), floor(y / l), floor(z / l))                      (Eq. 2)
//! h = |(ix·p1) xor (iy·p2) xor (iz·p3)| mod n                          (Eq. 1)
//! cell_id = iz·p1·p1 + iy·p1 + ix                                      (Eq. 3)
//! ```
//!
//! with the primes of Teschner et al. 2003, `p1 = 73 856 093`, `p2 = 19 349 663`,
//! `p3 = 83 492 791`, all products in wrapping `i64` arithmetic. No bounding box of the domain
//! is needed: any cell, however far, hashes to one of `n` buckets. Because `n` is far smaller
//! than the number of cells, different cells share buckets; every entry therefore stores the
//! `cell_id` of its cell and queries only return entries whose `cell_id` matches, so
//! primitives of different cells are never compared.
//!
//! ## How unique `cell_id` is
//!
//! Eq. 3 is a mixed-radix number with radix `p1`, computed modulo `2^64`. Two cells differing
//! by `(dx, dy, dz)` get the same id iff `dx + p1·dy + p1²·dz ≡ 0 (mod 2^64)`. With
//! `|dx| < p1`, `|dy| < p1 − 1` the first two terms stay below `p1²` in magnitude, so a
//! non-zero `dz` cannot cancel them, and with `|dz| < 2^64 / p1² − 1 ≈ 3380` the sum cannot
//! reach `2^64`: the id is exact for cells less than `7.3e7` apart in x and y and `3380` apart
//! in z (33 m with centimetre cells). Farther apart, two cells *may* share an id, but they must
//! then also share a bucket (probability ≈ `1/n`) to be confused. For the 27-cell
//! neighbourhoods of the self-collider it is always exact.
//!
//! ## Build: a parallel counting sort
//!
//! Every substep the table is rebuilt from scratch in four parallel passes, with memory
//! proportional to the number of (primitive, cell) insertions and never to the size of space:
//!
//! 1. each block of primitives lists its insertions `(bucket, cell_id, index)` in its own
//!    buffer; a prefix sum over the blocks places the buffers in one key array;
//! 2. an atomic counter per bucket counts the keys of each bucket; a prefix sum over the `n`
//!    buckets gives the bucket ranges (`starts`);
//! 3. keys are scattered to their bucket's range with an atomic cursor per bucket;
//! 4. each bucket is sorted by `(cell_id, index)`, which makes the result independent of the
//!    thread schedule (deterministic) and lets a query binary-search its cell in the bucket.
//!
//! [`SpatialHash::build_with_masks`] files primitives for up to 32 states at once (a moving
//! collider at each substep of a frame): each entry carries a mask of the states it is filed
//! for, and [`SpatialHash::query_cell_for`] reads one state's entries, so a table built once
//! answers each state as a table of its own would.
//!
//! The table size `n` is the next power of two at least twice the number of primitives (so
//! `mod n` is a mask). What loads a bucket is the number of distinct *cells*, which is at most
//! the number of insertions and for meshes well below it (the 47.5k-triangle body with cells of
//! the mean edge length fills 18.7k cells with 140k insertions). All buffers keep their
//! capacity between builds: once warmed up, a rebuild of the same size does not allocate.
//!
//! ## A property of Eq. 1
//!
//! For small coordinates `−a ≈ ¬a` in two's complement, so flipping the sign of two of the
//! three coordinates nearly cancels in the xor, and `|·|` folds the sign of the result: cells
//! mirrored through an axis, e.g. `(x, y, z)` and `(−x, y, −z)`, land in the same bucket far
//! more often than chance. A mirror-symmetric body therefore sees more shared buckets than a
//! random hash would give (on the body above, 34 % of the cells share their bucket with another
//! cell where a uniform hash would give 13 %). Correctness is unaffected (the `cell_id`
//! check), only the length of some scans.

use std::sync::atomic::{AtomicBool, AtomicU32, Ordering};

use rayon::prelude::*;

use crate::error::{Result, TailorError};

/// First prime of Eq. 1 and the radix of Eq. 3 (Teschner et al. 2003).
pub const P1: i64 = 73_856_093;
/// Second prime of Eq. 1.
pub const P2: i64 = 19_349_663;
/// Third prime of Eq. 1.
pub const P3: i64 = 83_492_791;

/// Integer coordinates of a cell (Eq. 2).
pub type Cell = [i64; 3];

/// Primitives per work item of the insertion pass.
const PRIM_BLOCK: usize = 1024;
/// Most keys one block of primitives may insert (64 MiB of keys): more means a cell size far
/// too small for the primitives, refused before memory runs out.
const MAX_BLOCK_KEYS: usize = 1 << 22;
/// Buckets per work item of the bucket-sorting pass.
const BUCKET_BLOCK: usize = 4096;

/// Cell coordinates are clamped to `±2^62` so that neighbour offsets never overflow.
const CELL_LIMIT: f32 = 4.6e18;

/// The cell containing `p` for a cell side `l` (Eq. 2). Non-finite or absurdly large
/// coordinates land in an arbitrary (clamped) cell rather than panicking.
#[inline]
pub fn cell_of(p: [f32; 3], l: f32) -> Cell {
    // `f32::floor` is a libm call on baseline x86-64 (no SSE4.1); truncate and correct instead.
    let c = |v: f32| {
        let q = (v / l).clamp(-CELL_LIMIT, CELL_LIMIT);
        let t = q as i64;
        t - ((t as f32) > q) as i64
    };
    [c(p[0]), c(p[1]), c(p[2])]
}

/// Calls `visit` with each cell the segment `from → to` passes through, in order from
/// `from`'s cell, at most `max` of them (a 3D DDA: Amanatides and Woo 1987). Returns false
/// when it stopped at `max` before reaching `to`'s cell. Cells are those of [`cell_of`]; where
/// the segment runs exactly through a cell edge or corner only one of the cells meeting there
/// is visited (a caller needing those pads its primitives, as the mesh colliders do).
pub fn segment_cells(from: [f32; 3], to: [f32; 3], l: f32, max: usize, mut visit: impl FnMut(Cell)) -> bool {
    let (mut c, end) = (cell_of(from, l), cell_of(to, l));
    // Per axis: the step, the segment parameter of the next cell face, and between faces.
    let (mut step, mut next, mut delta) = ([0i64; 3], [f32::INFINITY; 3], [f32::INFINITY; 3]);
    for k in 0..3 {
        let d = to[k] - from[k];
        if c[k] != end[k] && d != 0.0 {
            step[k] = if d > 0.0 { 1 } else { -1 };
            let face = (c[k] + (d > 0.0) as i64) as f32 * l;
            next[k] = ((face - from[k]) / d).max(0.0);
            delta[k] = l / d.abs();
        }
    }
    for _ in 0..max {
        visit(c);
        if c == end {
            return true;
        }
        // The axis whose face comes first; an axis already at its end cell never steps, so
        // rounding cannot walk past `to`.
        let k = (0..3).filter(|&k| c[k] != end[k]).min_by(|&a, &b| next[a].total_cmp(&next[b]));
        let Some(k) = k else { return true };
        c[k] += step[k];
        next[k] += delta[k];
    }
    false
}

/// Eq. 3, wrapping: `iz·p1·p1 + iy·p1 + ix`.
#[inline]
pub fn cell_id(c: Cell) -> i64 {
    c[2].wrapping_mul(P1).wrapping_mul(P1).wrapping_add(c[1].wrapping_mul(P1)).wrapping_add(c[0])
}

/// Eq. 1 for a table of `mask + 1` buckets (a power of two, so `mod n` is `& mask`).
#[inline]
pub fn bucket_of(c: Cell, mask: u64) -> usize {
    let h = c[0].wrapping_mul(P1) ^ c[1].wrapping_mul(P2) ^ c[2].wrapping_mul(P3);
    (h.unsigned_abs() & mask) as usize
}

/// One insertion as stored in the table: the primitive, the id of the cell it was filed in,
/// and the set of states it is filed there for (bit `j`: state `j`; all ones unless the
/// build was [`build_with_masks`](SpatialHash::build_with_masks)).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Entry {
    pub cell_id: i64,
    pub index: u32,
    pub mask: u32,
}

#[derive(Debug, Clone, Copy, Default)]
struct Key {
    cell_id: i64,
    bucket: u32,
    index: u32,
    mask: u32,
}

/// A spatial hash table of primitive indices, rebuilt every substep. See the module docs.
#[derive(Debug)]
pub struct SpatialHash {
    cell_size: f32,
    mask: u64,
    /// Bucket `b` holds `entries[starts[b]..starts[b + 1]]`, sorted by `(cell_id, index)`.
    starts: Vec<u32>,
    entries: Vec<Entry>,
    // Scratch kept between builds.
    keys: Vec<Key>,
    block_keys: Vec<Vec<Key>>,
    block_offsets: Vec<usize>,
    cursors: Vec<AtomicU32>,
    slots: Vec<AtomicU32>,
}

impl Default for SpatialHash {
    fn default() -> Self {
        Self::new()
    }
}

impl SpatialHash {
    /// Heap bytes of the table and of the scratch it keeps between builds.
    pub fn memory_bytes(&self) -> usize {
        use std::mem::size_of;
        self.starts.capacity() * size_of::<u32>()
            + self.entries.capacity() * size_of::<Entry>()
            + self.keys.capacity() * size_of::<Key>()
            + self.block_keys.iter().map(|k| k.capacity() * size_of::<Key>()).sum::<usize>()
            + self.block_offsets.capacity() * size_of::<usize>()
            + (self.cursors.capacity() + self.slots.capacity()) * size_of::<AtomicU32>()
    }

    /// An empty table (every query returns nothing until the first build).
    pub fn new() -> Self {
        Self {
            cell_size: 1.0,
            mask: 0,
            starts: vec![0, 0],
            entries: Vec::new(),
            keys: Vec::new(),
            block_keys: Vec::new(),
            block_offsets: Vec::new(),
            cursors: Vec::new(),
            slots: Vec::new(),
        }
    }

    /// Cell side `l` of the last build.
    pub fn cell_size(&self) -> f32 {
        self.cell_size
    }
    /// Number of buckets `n`.
    pub fn num_buckets(&self) -> usize {
        self.mask as usize + 1
    }
    /// Number of (primitive, cell) insertions stored.
    pub fn num_entries(&self) -> usize {
        self.entries.len()
    }
    /// Length of the fullest bucket (a measure of hash quality).
    pub fn max_bucket_len(&self) -> usize {
        self.starts.windows(2).map(|w| (w[1] - w[0]) as usize).max().unwrap_or(0)
    }
    /// The cell containing `p` with this table's cell size.
    #[inline]
    pub fn cell_of(&self, p: [f32; 3]) -> Cell {
        cell_of(p, self.cell_size)
    }
    /// All entries of the bucket `cell` hashes to, whatever their cell.
    #[inline]
    pub fn bucket_entries(&self, cell: Cell) -> &[Entry] {
        let b = bucket_of(cell, self.mask);
        &self.entries[self.starts[b] as usize..self.starts[b + 1] as usize]
    }

    /// Indices of the primitives filed in `cell`, in increasing order: the entries of its
    /// bucket whose `cell_id` matches.
    #[inline]
    pub fn query_cell(&self, cell: Cell) -> impl Iterator<Item = u32> + '_ {
        let id = cell_id(cell);
        let bucket = self.bucket_entries(cell);
        let first = bucket.partition_point(|e| e.cell_id < id);
        bucket[first..].iter().take_while(move |e| e.cell_id == id).map(|e| e.index)
    }

    /// [`query_cell`](Self::query_cell) for the states in `bits`: the primitives filed in
    /// `cell` for one of them.
    #[inline]
    pub fn query_cell_for(&self, cell: Cell, bits: u32) -> impl Iterator<Item = u32> + '_ {
        let id = cell_id(cell);
        let bucket = self.bucket_entries(cell);
        let first = bucket.partition_point(|e| e.cell_id < id);
        bucket[first..].iter().take_while(move |e| e.cell_id == id).filter(move |e| e.mask & bits != 0).map(|e| e.index)
    }

    /// Files point `i` = `(x[i], y[i], z[i])` in the cell containing it.
    pub fn build_points(&mut self, x: &[f32], y: &[f32], z: &[f32], cell_size: f32) -> Result<()> {
        if x.len() != y.len() || x.len() != z.len() {
            return Err(TailorError::shape(
                "spatial hash points",
                format!("coordinate arrays differ in length: x {}, y {}, z {}", x.len(), y.len(), z.len()),
            ));
        }
        self.build_with(x.len(), cell_size, |i, emit| emit(cell_of([x[i], y[i], z[i]], cell_size)))
    }

    /// Generic build: `visit(i, emit)` must call `emit(cell)` once for every cell primitive `i`
    /// is filed in (never twice for the same cell).
    pub fn build_with<F>(&mut self, num_primitives: usize, cell_size: f32, visit: F) -> Result<()>
    where
        F: Fn(usize, &mut dyn FnMut(Cell)) + Sync,
    {
        self.build_with_masks(num_primitives, cell_size, |i, emit| visit(i, &mut |c| emit(c, u32::MAX)))
    }

    /// One table for up to 32 states of the primitives (a moving collider at each substep of
    /// a frame): `visit(i, emit)` calls `emit(cell, mask)` once for every cell primitive `i`
    /// is filed in for some state, `mask` saying for which (bit `j`: state `j`);
    /// [`query_cell_for`](Self::query_cell_for) then gives each state's own table.
    pub fn build_with_masks<F>(&mut self, num_primitives: usize, cell_size: f32, visit: F) -> Result<()>
    where
        F: Fn(usize, &mut dyn FnMut(Cell, u32)) + Sync,
    {
        if !(cell_size.is_finite() && cell_size > 0.0) {
            return Err(TailorError::setting("cell_size", cell_size, "the hash cell size must be positive and finite"));
        }
        if num_primitives > u32::MAX as usize {
            return Err(TailorError::setting("num_primitives", num_primitives, "at most 2^32 - 1 primitives"));
        }
        self.cell_size = cell_size;

        let n = (2 * num_primitives).max(2).next_power_of_two();
        let mask = (n - 1) as u64;
        self.mask = mask;

        // Pass 1: each block of primitives collects its keys in its own reusable buffer, then
        // the buffers are concatenated (a prefix sum over blocks places them).
        let num_blocks = num_primitives.div_ceil(PRIM_BLOCK);
        if self.block_keys.len() < num_blocks {
            self.block_keys.resize_with(num_blocks, Vec::new);
        }
        let overflow = AtomicBool::new(false);
        self.block_keys[..num_blocks].par_iter_mut().enumerate().for_each(|(b, keys)| {
            keys.clear();
            for i in b * PRIM_BLOCK..((b + 1) * PRIM_BLOCK).min(num_primitives) {
                visit(i, &mut |c, bits| {
                    if keys.len() < MAX_BLOCK_KEYS {
                        keys.push(Key {
                            cell_id: cell_id(c),
                            bucket: bucket_of(c, mask) as u32,
                            index: i as u32,
                            mask: bits,
                        });
                    } else {
                        overflow.store(true, Ordering::Relaxed);
                    }
                });
            }
        });
        if overflow.load(Ordering::Relaxed) {
            return Err(TailorError::setting(
                "cell_size",
                cell_size,
                format!(
                    "over {MAX_BLOCK_KEYS} hash insertions for {PRIM_BLOCK} primitives: the cells are far too small"
                ),
            ));
        }
        self.block_offsets.clear();
        self.block_offsets.push(0);
        let mut total = 0usize;
        for keys in &self.block_keys[..num_blocks] {
            total += keys.len();
            self.block_offsets.push(total);
        }
        if total >= u32::MAX as usize / 2 {
            return Err(TailorError::setting(
                "cell_size",
                cell_size,
                format!("{total} hash insertions: the cells are far too small for the primitives"),
            ));
        }
        self.keys.clear();
        self.keys.resize(total, Key::default());
        let (offsets, block_keys) = (&self.block_offsets, &self.block_keys);
        split_ranges(&mut self.keys, 0, num_blocks, &|b| offsets[b], &|b, keys| keys.copy_from_slice(&block_keys[b]));

        // Pass 2: bucket sizes, prefix sum.
        if self.cursors.len() < n {
            self.cursors.resize_with(n, || AtomicU32::new(0));
        }
        let cursors = &self.cursors[..n];
        cursors.par_iter().for_each(|c| c.store(0, Ordering::Relaxed));
        self.keys.par_iter().for_each(|k| {
            cursors[k.bucket as usize].fetch_add(1, Ordering::Relaxed);
        });
        self.starts.clear();
        self.starts.resize(n + 1, 0);
        let mut acc = 0u32;
        for (b, c) in cursors.iter().enumerate() {
            self.starts[b] = acc;
            acc += c.load(Ordering::Relaxed);
            c.store(self.starts[b], Ordering::Relaxed);
        }
        self.starts[n] = acc;

        // Pass 3: scatter key numbers to their bucket ranges.
        if self.slots.len() < total {
            self.slots.resize_with(total, || AtomicU32::new(0));
        }
        let slots = &self.slots[..total];
        self.keys.par_iter().enumerate().for_each(|(i, k)| {
            let pos = cursors[k.bucket as usize].fetch_add(1, Ordering::Relaxed);
            slots[pos as usize].store(i as u32, Ordering::Relaxed);
        });

        // Pass 4: gather entries and sort each bucket (deterministic order).
        self.entries.clear();
        self.entries.resize(total, Entry::default());
        let (starts, keys) = (&self.starts, &self.keys);
        let num_groups = n.div_ceil(BUCKET_BLOCK);
        split_ranges(&mut self.entries, 0, num_groups, &|g| starts[(g * BUCKET_BLOCK).min(n)] as usize, &|g, out| {
            let base = starts[g * BUCKET_BLOCK] as usize;
            for b in g * BUCKET_BLOCK..((g + 1) * BUCKET_BLOCK).min(n) {
                let (lo, hi) = (starts[b] as usize, starts[b + 1] as usize);
                let bucket = &mut out[lo - base..hi - base];
                for (e, pos) in bucket.iter_mut().zip(lo..hi) {
                    let k = keys[slots[pos].load(Ordering::Relaxed) as usize];
                    *e = Entry { cell_id: k.cell_id, index: k.index, mask: k.mask };
                }
                if bucket.len() > 1 {
                    bucket.sort_unstable_by_key(|e| (e.cell_id, e.index));
                }
            }
        });
        Ok(())
    }
}

/// Runs `f(block, part)` in parallel for blocks `lo..hi`, where block `b` owns
/// `data[offset(b) - offset(lo) .. offset(b + 1) - offset(lo)]`. Splits by halving with
/// `rayon::join`, so the disjoint mutable parts need no allocation and no `unsafe`.
fn split_ranges<T, O, F>(data: &mut [T], lo: usize, hi: usize, offset: &O, f: &F)
where
    T: Send,
    O: Fn(usize) -> usize + Sync,
    F: Fn(usize, &mut [T]) + Sync,
{
    match hi - lo {
        0 => {}
        1 => f(lo, data),
        len => {
            let mid = lo + len / 2;
            let (a, b) = data.split_at_mut(offset(mid) - offset(lo));
            rayon::join(|| split_ranges(a, lo, mid, offset, f), || split_ranges(b, mid, hi, offset, f));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_util::Rng;

    /// A table built with masks answers each state's query with exactly the primitives filed
    /// there for that state (and `query_cell` with all of them), in increasing order.
    #[test]
    fn masked_queries_return_each_states_primitives() {
        let mut rng = Rng::new(9);
        let n = 3000;
        let filed: Vec<Vec<(Cell, u32)>> = (0..n)
            .map(|_| {
                let base = [0, 1, 2].map(|_| (rng.f32() * 20.0) as i64 - 10);
                (0..1 + rng.next_u64() % 4)
                    .map(|d| ([base[0] + d as i64, base[1], base[2]], 1 + (rng.next_u64() % 0xffff) as u32))
                    .collect()
            })
            .collect();
        let mut h = SpatialHash::new();
        h.build_with_masks(n, 0.01, |i, emit| {
            for &(c, bits) in &filed[i] {
                emit(c, bits);
            }
        })
        .unwrap();
        for c in (0..400).map(|_| [0, 1, 2].map(|_| (rng.f32() * 24.0) as i64 - 12)) {
            for bit in [1u32, 1 << 3, 1 << 15, u32::MAX] {
                let want: Vec<u32> = (0..n as u32)
                    .filter(|&i| filed[i as usize].iter().any(|&(fc, bits)| fc == c && bits & bit != 0))
                    .collect();
                assert_eq!(h.query_cell_for(c, bit).collect::<Vec<_>>(), want, "cell {c:?}, bit {bit:#x}");
            }
            let all: Vec<u32> = h.query_cell(c).collect();
            assert_eq!(all, h.query_cell_for(c, u32::MAX).collect::<Vec<_>>());
        }
    }

    #[test]
    fn queries_return_exactly_the_points_of_the_cell() {
        let mut rng = Rng::new(1);
        let mut h = SpatialHash::new();
        for round in 0..10 {
            let n = 50 + (rng.f32() * 3000.0) as usize;
            // Clustered points far from the origin, negative coordinates included, so that
            // many distinct cells share buckets.
            let centre = rng.vec3(1000.0);
            let spread = 0.01 + rng.f32();
            let (mut x, mut y, mut z) = (vec![], vec![], vec![]);
            for _ in 0..n {
                let p = centre + rng.vec3(spread);
                x.push(p.x);
                y.push(p.y);
                z.push(p.z);
            }
            let l = 0.01 + 0.1 * rng.f32();
            h.build_points(&x, &y, &z, l).unwrap();
            assert_eq!(h.num_entries(), n);
            assert!(h.num_buckets() >= 2 * n && h.num_buckets().is_power_of_two());
            let cells: Vec<Cell> = (0..n).map(|i| cell_of([x[i], y[i], z[i]], l)).collect();
            for c in &cells {
                let got: Vec<u32> = h.query_cell(*c).collect();
                let want: Vec<u32> = (0..n as u32).filter(|&i| cells[i as usize] == *c).collect();
                assert_eq!(got, want, "round {round}");
            }
            // An empty neighbour cell returns nothing even when its bucket is occupied.
            let far = [cells[0][0] + 1_000_003, cells[0][1], cells[0][2]];
            assert!(h.query_cell(far).all(|i| cells[i as usize] == far));
        }
    }

    #[test]
    fn build_is_deterministic_across_thread_counts() {
        let mut rng = Rng::new(9);
        let (mut x, mut y, mut z) = (vec![], vec![], vec![]);
        for _ in 0..20_000 {
            let p = rng.vec3(0.5);
            x.push(p.x);
            y.push(p.y);
            z.push(p.z);
        }
        let build = |threads: usize| {
            let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
            pool.install(|| {
                let mut h = SpatialHash::new();
                h.build_points(&x, &y, &z, 0.02).unwrap();
                (h.starts.clone(), h.entries.clone())
            })
        };
        assert_eq!(build(1), build(4));
    }

    /// The DDA visits exactly the cells that points sampled densely along the segment fall
    /// in (segments in every direction, some through many cells), each once, in order, and
    /// stops at `max`.
    #[test]
    fn segment_cells_are_the_cells_the_segment_passes_through() {
        let mut rng = Rng::new(5);
        for round in 0..500 {
            let l = 0.01 + 0.05 * rng.f32();
            let a = rng.vec3(0.3);
            let b = if round % 5 == 0 { a + glam::Vec3::new(rng.f32() * 0.2, 0.0, 0.0) } else { a + rng.vec3(0.2) };
            let mut got = Vec::new();
            assert!(segment_cells(a.into(), b.into(), l, 10_000, |c| got.push(c)));
            let mut want: Vec<Cell> = Vec::new();
            for k in 0..=20_000 {
                let c = cell_of(a.lerp(b, k as f32 / 20_000.0).into(), l);
                if want.last() != Some(&c) {
                    want.push(c);
                }
            }
            // Sampling can only miss a cell the segment cuts over less than a sample's length
            // (a corner): every sampled cell is visited, in the same order, and every visited
            // cell is a neighbour of the previous one across one face.
            let mut it = got.iter();
            for c in &want {
                assert!(it.any(|g| g == c), "round {round}: sampled cell {c:?} not visited in order");
            }
            assert_eq!(got.first(), Some(&cell_of(a.into(), l)));
            assert_eq!(got.last(), Some(&cell_of(b.into(), l)));
            for w in got.windows(2) {
                let d: i64 = (0..3).map(|k| (w[1][k] - w[0][k]).abs()).sum();
                assert_eq!(d, 1, "round {round}: {:?} -> {:?} is not a face step", w[0], w[1]);
            }
            let mut capped = 0;
            let full = got.len();
            let done = segment_cells(a.into(), b.into(), l, 2, |_| capped += 1);
            assert_eq!(capped, full.min(2));
            assert_eq!(done, full <= 2);
        }
    }

    #[test]
    fn cell_id_is_exact_near_the_origin_and_hash_is_eq1() {
        let c = [3, -2, 5];
        assert_eq!(cell_id(c), 5 * P1 * P1 - 2 * P1 + 3);
        assert_eq!(bucket_of(c, 1023), ((3 * P1) ^ (-2 * P2) ^ (5 * P3)).unsigned_abs() as usize % 1024);
        assert_eq!(cell_of([-0.001, 0.0, 0.0299], 0.01), [-1, 0, 2]);
        let mut h = SpatialHash::new();
        assert!(h.build_points(&[0.0], &[0.0], &[0.0], -1.0).is_err());
        assert!(h.build_points(&[0.0], &[0.0], &[], 1.0).is_err());
        assert_eq!(h.query_cell([0, 0, 0]).count(), 0);
    }
}
