//! Host side of `coarse.wgsl`: the two-level global step's coarse correction after each
//! iteration's sweep (residual, restriction, one workgroup's conjugate gradients, prolongation).

use super::Buffers;

pub const SOURCE: &str = concat!(include_str!("common.wgsl"), include_str!("row.wgsl"), include_str!("coarse.wgsl"));
pub const RESIDUAL_ENTRY: &str = "residual";
pub const RESTRICT_ENTRY: &str = "restrict_residual";
pub const SOLVE_ENTRY: &str = "solve";
pub const PROLONG_ENTRY: &str = "prolong";
pub const PROLONG_HISTORY_ENTRY: &str = "prolong_history";
pub const WORKGROUP: u32 = 64;

/// Vectors of the coarse grid in `cw` (r, e, p, q, and the diagonal with its inverse).
pub const SECTIONS: usize = 5;

/// The bindings every entry point draws from (each binds only those it uses).
pub fn entries(b: &Buffers) -> Vec<(u32, &wgpu::Buffer)> {
    vec![(0, &b.params), (1, &b.state)]
}

pub fn residual_entries(b: &Buffers) -> Vec<(u32, &wgpu::Buffer)> {
    let mut e = entries(b);
    e.extend([(2, &b.idx), (3, &b.fdata), (4, &b.x), (5, &b.rhs), (6, &b.slots), (7, &b.contacts), (8, &b.cres)]);
    e
}

pub fn restrict_entries(b: &Buffers) -> Vec<(u32, &wgpu::Buffer)> {
    let mut e = entries(b);
    e.extend([(2, &b.idx), (3, &b.fdata), (8, &b.cres), (9, &b.cwork)]);
    e
}

pub fn solve_entries(b: &Buffers) -> Vec<(u32, &wgpu::Buffer)> {
    let mut e = entries(b);
    e.extend([(2, &b.idx), (3, &b.fdata), (9, &b.cwork)]);
    e
}

pub fn prolong_entries(b: &Buffers) -> Vec<(u32, &wgpu::Buffer)> {
    let mut e = entries(b);
    e.extend([(2, &b.idx), (4, &b.x), (9, &b.cwork)]);
    e
}

pub fn prolong_history_entries(b: &Buffers) -> Vec<(u32, &wgpu::Buffer)> {
    let mut e = prolong_entries(b);
    e.push((10, &b.cur));
    e
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gpu::common::validate_wgsl;

    #[test]
    fn coarse_wgsl_validates_and_shares_the_cpus_constants() {
        let m = validate_wgsl("coarse", SOURCE).unwrap();
        for e in [RESIDUAL_ENTRY, RESTRICT_ENTRY, SOLVE_ENTRY, PROLONG_ENTRY, PROLONG_HISTORY_ENTRY] {
            assert!(m.entry_points.iter().any(|p| p.name == e), "{e}");
        }
        assert_eq!(crate::solver::stages::coarse::NONE, 0xffff_ffff);
        assert!(SOURCE.contains("const NONE: u32 = 0xffffffffu;"));
    }
}
