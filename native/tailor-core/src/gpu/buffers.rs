//! The per-simulation GPU buffers (every buffer the stages bind; names match the WGSL
//! variables) and their element capacities: buffers are reused while a new upload fits them.

use super::common::{Collider, Contact, Params, StepState};
use super::{attach, Meshes, Particle};

/// Every GPU buffer the stages bind (names match the WGSL variables).
pub struct Buffers {
    pub params: wgpu::Buffer,
    pub state: wgpu::Buffer,
    pub particles: wgpu::Buffer,
    pub x: wgpu::Buffer,
    pub v: wgpu::Buffer,
    pub x_start: wgpu::Buffer,
    pub rhs: wgpu::Buffer,
    pub prev: wgpu::Buffer,
    pub cur: wgpu::Buffer,
    pub slots: wgpu::Buffer,
    pub norms: wgpu::Buffer,
    /// The update norms' partial sums (`reduce_partial`), one per workgroup.
    pub partials: wgpu::Buffer,
    pub idx: wgpu::Buffer,
    pub fdata: wgpu::Buffer,
    pub colours: wgpu::Buffer,
    pub contacts: wgpu::Buffer,
    pub colliders: wgpu::Buffer,
    /// Mesh colliders: the per-frame uniform, vertex sections (see `mesh_query.wgsl`), and the
    /// hash table's bucket counts, starts and entries, with its size uniform.
    pub meshes: wgpu::Buffer,
    pub mverts: wgpu::Buffer,
    pub mcounts: wgpu::Buffer,
    pub mtable: wgpu::Buffer,
    pub mesh_table_info: wgpu::Buffer,
    /// The collider table's block sums (`hash.wgsl`'s scan), one per block of buckets.
    pub mblocks: wgpu::Buffer,
    /// Self-collision: the particle table and each particle's averaged correction.
    pub scounts: wgpu::Buffer,
    pub stable: wgpu::Buffer,
    pub sdelta: wgpu::Buffer,
    pub self_table_info: wgpu::Buffer,
    /// The particle table's block sums.
    pub sblocks: wgpu::Buffer,
    /// Collider attachments (`attach.wgsl`) and their count.
    pub attachments: wgpu::Buffer,
    pub attach_info: wgpu::Buffer,
    /// Seam pairs' closing state (`close_seams.wgsl`), one vec4 per pair.
    pub closing: wgpu::Buffer,
    /// The two-level step (`coarse.wgsl`): each particle's residual and contact weight, and the
    /// coarse grid's vectors.
    pub cres: wgpu::Buffer,
    pub cwork: wgpu::Buffer,
    pub(super) x_backup: wgpu::Buffer,
    pub(super) v_backup: wgpu::Buffer,
    pub(super) state_backup: wgpu::Buffer,
    pub(super) readback: wgpu::Buffer,
    pub(super) caps: Capacities,
}

/// Element capacities of the size-dependent buffers; buffers are reused while they fit.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub(super) struct Capacities {
    pub(super) n: usize,
    pub(super) slots: usize,
    pub(super) idx: usize,
    pub(super) fdata: usize,
    pub(super) colours: usize,
    pub(super) colliders: usize,
    pub(super) mesh_verts: usize,
    pub(super) mesh_tris: usize,
    pub(super) mesh_buckets: usize,
    pub(super) mesh_entries: usize,
    pub(super) self_buckets: usize,
    pub(super) attachments: usize,
    pub(super) seam_pairs: usize,
    /// Aggregates of the two-level step's coarse grid (0: off).
    pub(super) coarse: usize,
}

impl Capacities {
    pub(super) fn fits(&self, need: &Capacities) -> bool {
        need.n <= self.n
            && need.slots <= self.slots
            && need.idx <= self.idx
            && need.fdata <= self.fdata
            && need.colours <= self.colours
            && need.colliders <= self.colliders
            && need.mesh_verts <= self.mesh_verts
            && need.mesh_tris <= self.mesh_tris
            && need.mesh_buckets <= self.mesh_buckets
            && need.mesh_entries <= self.mesh_entries
            && need.self_buckets <= self.self_buckets
            && need.attachments <= self.attachments
            && need.seam_pairs <= self.seam_pairs
            && need.coarse <= self.coarse
    }
}

pub(super) const VEC4: u64 = 16;
pub(super) const STATE_BYTES: u64 = std::mem::size_of::<StepState>() as u64;

impl Buffers {
    pub(super) fn new(device: &wgpu::Device, caps: Capacities, colour_stride: u64) -> Self {
        use wgpu::BufferUsages as U;
        let storage = U::STORAGE | U::COPY_DST | U::COPY_SRC;
        // wgpu rejects zero-sized bindings: every buffer holds at least one element.
        let mk = |label: &str, bytes: u64, usage: U| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: bytes.max(16).next_multiple_of(4),
                usage,
                mapped_at_creation: false,
            })
        };
        let n = caps.n as u64;
        Self {
            params: mk("params", std::mem::size_of::<Params>() as u64, U::UNIFORM | U::COPY_DST),
            state: mk("state", STATE_BYTES, storage),
            particles: mk("particles", n * std::mem::size_of::<Particle>() as u64, storage),
            x: mk("x", n * VEC4, storage),
            v: mk("v", n * VEC4, storage),
            x_start: mk("x_start", n * VEC4, storage),
            rhs: mk("rhs", n * VEC4, storage),
            prev: mk("prev", n * VEC4, storage),
            cur: mk("cur", n * VEC4, storage),
            slots: mk("slots", caps.slots as u64 * VEC4, storage),
            norms: mk("norms", n * 8, storage),
            partials: mk("partials", super::chebyshev::REDUCE as u64 * 8, storage),
            idx: mk("idx", caps.idx as u64 * 4, storage),
            fdata: mk("fdata", caps.fdata as u64 * 4, storage),
            colours: mk("colours", caps.colours.max(1) as u64 * colour_stride, U::UNIFORM | U::COPY_DST),
            contacts: mk("contacts", n * std::mem::size_of::<Contact>() as u64, storage),
            colliders: mk("colliders", caps.colliders.max(1) as u64 * std::mem::size_of::<Collider>() as u64, storage),
            meshes: mk("meshes", std::mem::size_of::<Meshes>() as u64, U::UNIFORM | U::COPY_DST),
            mverts: mk("mverts", (4 * caps.mesh_verts + caps.mesh_tris) as u64 * VEC4, storage),
            mcounts: mk("mcounts", caps.mesh_buckets as u64 * 4, storage),
            mtable: mk("mtable", (caps.mesh_buckets + 1 + 4 * caps.mesh_entries) as u64 * 4, storage),
            mesh_table_info: mk("mesh_table_info", 16, U::UNIFORM | U::COPY_DST),
            mblocks: mk("mblocks", super::hash::scan_blocks(caps.mesh_buckets) as u64 * 4, storage),
            scounts: mk("scounts", caps.self_buckets as u64 * 4, storage),
            stable: mk("stable", (caps.self_buckets + 1 + 4 * n as usize) as u64 * 4, storage),
            sdelta: mk("sdelta", n * VEC4, storage),
            self_table_info: mk("self_table_info", 16, U::UNIFORM | U::COPY_DST),
            sblocks: mk("sblocks", super::hash::scan_blocks(caps.self_buckets) as u64 * 4, storage),
            attachments: mk(
                "attachments",
                caps.attachments.max(1) as u64 * std::mem::size_of::<attach::Attachment>() as u64,
                storage,
            ),
            attach_info: mk("attach_info", std::mem::size_of::<attach::AttachInfo>() as u64, U::UNIFORM | U::COPY_DST),
            closing: mk("closing", caps.seam_pairs as u64 * VEC4, storage),
            // Only with a coarse grid: one element otherwise.
            cres: mk("cres", if caps.coarse > 0 { n * VEC4 } else { VEC4 }, storage),
            cwork: mk("cwork", (super::coarse::SECTIONS * caps.coarse) as u64 * VEC4, storage),
            x_backup: mk("x_backup", n * VEC4, storage),
            v_backup: mk("v_backup", n * VEC4, storage),
            state_backup: mk("state_backup", STATE_BYTES, storage),
            // Positions, the state, then the seam pairs' closing state.
            readback: mk("readback", n * VEC4 + STATE_BYTES + caps.seam_pairs as u64 * VEC4, U::MAP_READ | U::COPY_DST),
            caps,
        }
    }
}
