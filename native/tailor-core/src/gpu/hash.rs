//! Host side of `hash.wgsl`: the generic scan (three passes over blocks of buckets) and
//! per-bucket sort of a GPU hash build, bound once for the collider table and once for the
//! particle table. Composed as `common + collide_common + hash`.

pub const SOURCE: &str =
    concat!(include_str!("common.wgsl"), include_str!("collide_common.wgsl"), include_str!("hash.wgsl"));
pub const SCAN_BLOCKS_ENTRY: &str = "scan_blocks";
pub const SCAN_SUMS_ENTRY: &str = "scan_sums";
pub const SCAN_APPLY_ENTRY: &str = "scan_apply";
pub const SORT_ENTRY: &str = "sort";
pub const WORKGROUP: u32 = 64;
/// Buckets per workgroup of `scan_blocks` and `scan_apply` (`BLOCK` in `hash.wgsl`).
pub const BLOCK: usize = 1024;

/// Workgroups of `scan_blocks` and `scan_apply`, and block sums, for a table of `buckets`.
pub fn scan_blocks(buckets: usize) -> usize {
    buckets.div_ceil(BLOCK).max(1)
}

/// One table's buffers: its `TableInfo`, counts, table and block sums.
pub struct Table<'a> {
    pub info: &'a wgpu::Buffer,
    pub counts: &'a wgpu::Buffer,
    pub table: &'a wgpu::Buffer,
    pub block_sums: &'a wgpu::Buffer,
}

impl<'a> Table<'a> {
    /// Bindings of `scan_blocks`: sizes in, block sums out.
    pub fn scan_blocks_entries(&self) -> Vec<(u32, &'a wgpu::Buffer)> {
        vec![(2, self.info), (3, self.counts), (5, self.block_sums)]
    }

    /// Bindings of `scan_sums`: block sums to block starts, the total into the table.
    pub fn scan_sums_entries(&self) -> Vec<(u32, &'a wgpu::Buffer)> {
        vec![(2, self.info), (4, self.table), (5, self.block_sums)]
    }

    /// Bindings of `scan_apply`.
    pub fn scan_apply_entries(&self) -> Vec<(u32, &'a wgpu::Buffer)> {
        vec![(2, self.info), (3, self.counts), (4, self.table), (5, self.block_sums)]
    }

    /// Bindings of `sort`.
    pub fn sort_entries(&self) -> Vec<(u32, &'a wgpu::Buffer)> {
        vec![(2, self.info), (3, self.counts), (4, self.table)]
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gpu::common::validate_wgsl;

    #[test]
    fn the_block_size_is_the_shaders() {
        assert!(SOURCE.contains(&format!("const BLOCK: u32 = {BLOCK}u;")));
        assert!(SOURCE.contains("const SCAN: u32 = 256u;") && SOURCE.contains("const PER_THREAD: u32 = 4u;"));
        assert_eq!(BLOCK, 256 * 4);
        assert_eq!((scan_blocks(0), scan_blocks(1024), scan_blocks(1025)), (1, 1, 2));
    }

    /// The three scan passes on the GPU against an exclusive scan on the CPU: one block, a
    /// partial block, and more blocks than `scan_sums` has threads (two per thread).
    #[test]
    fn the_scan_passes_give_each_bucket_its_start_and_leave_it_as_the_cursor() {
        use crate::gpu::collide_common::TableInfo;
        use crate::gpu::context::GpuContext;
        use wgpu::util::DeviceExt;
        let ctx = match GpuContext::shared() {
            Ok((ctx, _)) => ctx,
            Err(e) if std::env::var("TAILOR_REQUIRE_GPU").as_deref() == Ok("1") => {
                panic!("TAILOR_REQUIRE_GPU=1 but no GPU adapter: {e}")
            }
            Err(e) => return println!("SKIP the scan passes: {e}"),
        };
        let (d, pl) = (&ctx.device, &ctx.pipelines);
        for nb in [7usize, 1024, 1500, 300_000] {
            let sizes: Vec<u32> = (0..nb as u32).map(|b| (b.wrapping_mul(2_654_435_761) >> 29) % 5).collect();
            let storage = wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC | wgpu::BufferUsages::COPY_DST;
            let init = |label, contents: &[u8], usage| {
                d.create_buffer_init(&wgpu::util::BufferInitDescriptor { label: Some(label), contents, usage })
            };
            let info = TableInfo { n_buckets: nb as u32, n_entries: 0, _pad0: 0, _pad1: 0 };
            let info = init("info", bytemuck::bytes_of(&info), wgpu::BufferUsages::UNIFORM);
            let counts = init("counts", bytemuck::cast_slice(&sizes), storage);
            let table = init("table", &vec![0u8; (nb + 1) * 4], storage);
            let block_sums = init("block_sums", &vec![0u8; scan_blocks(nb) * 4], storage);
            let t = Table { info: &info, counts: &counts, table: &table, block_sums: &block_sums };
            let groups = crate::gpu::pipelines::scan_groups(d, pl, "scan test", &t);
            let blocks = scan_blocks(nb) as u32;
            let mut enc = d.create_command_encoder(&Default::default());
            {
                let mut pass = enc.begin_compute_pass(&Default::default());
                for (p, g, n) in [
                    (&pl.scan_blocks, &groups[0], blocks),
                    (&pl.scan_sums, &groups[1], 1),
                    (&pl.scan_apply, &groups[2], blocks),
                ] {
                    pass.set_pipeline(p);
                    pass.set_bind_group(0, g, &[]);
                    pass.dispatch_workgroups(n, 1, 1);
                }
            }
            let read = d.create_buffer(&wgpu::BufferDescriptor {
                label: None,
                size: (2 * nb + 1) as u64 * 4,
                usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            });
            enc.copy_buffer_to_buffer(&table, 0, &read, 0, (nb + 1) as u64 * 4);
            enc.copy_buffer_to_buffer(&counts, 0, &read, (nb + 1) as u64 * 4, nb as u64 * 4);
            ctx.queue.submit([enc.finish()]);
            let bytes = crate::gpu::map_read(d, &read, (2 * nb + 1) as u64 * 4).unwrap();
            let got: &[u32] = bytemuck::cast_slice(&bytes);
            let mut want = Vec::with_capacity(nb + 1);
            let mut acc = 0u32;
            for &c in &sizes {
                want.push(acc);
                acc += c;
            }
            want.push(acc);
            let first_wrong = |a: &[u32], b: &[u32]| a.iter().zip(b).position(|(x, y)| x != y);
            assert_eq!(first_wrong(&got[..=nb], &want), None, "starts and total, {nb} buckets: first wrong bucket");
            assert_eq!(first_wrong(&got[nb + 1..], &want[..nb]), None, "cursors, {nb} buckets: first wrong bucket");
        }
    }

    #[test]
    fn hash_wgsl_validates() {
        let m = validate_wgsl("hash", SOURCE).unwrap();
        for e in [SCAN_BLOCKS_ENTRY, SCAN_SUMS_ENTRY, SCAN_APPLY_ENTRY, SORT_ENTRY] {
            assert!(m.entry_points.iter().any(|p| p.name == e), "{e}");
        }
    }
}
