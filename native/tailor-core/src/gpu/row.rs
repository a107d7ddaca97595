//! `row.wgsl`: one row of the global step's system (`GlobalSystem::row`'s sums, in its order),
//! included by the sweep (`gauss_seidel`) and the two-level step's residual (`coarse`), which
//! declare the buffers it reads. It has no entry point of its own; it is validated as part of
//! those stages.

pub const SOURCE: &str = include_str!("row.wgsl");

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gpu::common::validate_wgsl;

    /// Both stages that solve or measure a row read this one, and validate with it.
    #[test]
    fn the_sweep_and_the_residual_share_the_row() {
        for (name, src) in [("gauss_seidel", crate::gpu::gauss_seidel::SOURCE), ("coarse", crate::gpu::coarse::SOURCE)]
        {
            assert!(src.contains(SOURCE), "{name} does not include row.wgsl");
            validate_wgsl(name, src).unwrap();
        }
    }
}
