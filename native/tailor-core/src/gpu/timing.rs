//! Per-stage GPU times from timestamp queries: a timestamp before a frame's first dispatch
//! and one after each run of dispatches of one stage (`plan::stage_marks`), resolved and read
//! back with the frame; each stage's time is the sum of its runs. Needs the device feature
//! `TIMESTAMP_QUERY_INSIDE_PASSES` (Vulkan, DX12, Metal on AMD and Intel) and stage timing on
//! (`GpuSolver::set_stage_timing`, off by default: the timestamps cost the frame 5-9 % on
//! lavapipe); otherwise a frame reports its wall time as the global stage.

use crate::solver::{Stage, StageTimings};

/// Set to `1` to turn per-stage GPU times on for every GPU simulation of the process.
pub const STAGE_TIMES_ENV: &str = "TAILOR_GPU_STAGE_TIMES";

/// Timestamps one frame may write (wgpu's limit on a query set).
pub(super) const MAX_QUERIES: u32 = wgpu::QUERY_SET_MAX_QUERIES;

/// A simulation's query set and the buffers its timestamps go through.
pub(super) struct Timing {
    pub(super) set: wgpu::QuerySet,
    pub(super) resolve: wgpu::Buffer,
    pub(super) read: wgpu::Buffer,
}

impl Timing {
    pub(super) fn new(device: &wgpu::Device) -> Self {
        let bytes = MAX_QUERIES as u64 * 8;
        Timing {
            set: device.create_query_set(&wgpu::QuerySetDescriptor {
                label: Some("stage timestamps"),
                ty: wgpu::QueryType::Timestamp,
                count: MAX_QUERIES,
            }),
            resolve: device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("timestamps"),
                size: bytes,
                usage: wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
                mapped_at_creation: false,
            }),
            read: device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("timestamps readback"),
                size: bytes,
                usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            }),
        }
    }
}

/// Seconds per stage from the frame's timestamps `ticks` (one more than `marks`) at
/// `period` nanoseconds a tick.
pub(super) fn stage_times(marks: &[(usize, Stage)], ticks: &[u64], period: f32) -> StageTimings {
    let mut t = StageTimings::default();
    for (m, &(_, stage)) in marks.iter().enumerate() {
        let (a, b) = (ticks[m], ticks[m + 1]);
        t[stage] += b.saturating_sub(a) as f64 * period as f64 * 1e-9;
    }
    t
}

/// Seconds per kernel from a profiled frame's timestamps: `kernels[m]` names the dispatch
/// that mark `m` follows (one mark per dispatch); each kernel's dispatches summed, in the order
/// each first ran.
pub(super) fn kernel_times(kernels: &[&'static str], ticks: &[u64], period: f32) -> Vec<(&'static str, f64)> {
    let mut t: Vec<(&'static str, f64)> = Vec::new();
    for (m, &name) in kernels.iter().enumerate() {
        let s = ticks[m + 1].saturating_sub(ticks[m]) as f64 * period as f64 * 1e-9;
        match t.iter_mut().find(|(k, _)| *k == name) {
            Some(e) => e.1 += s,
            None => t.push((name, s)),
        }
    }
    t
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_run_of_a_stage_counts_in_that_stage() {
        let marks = [(0, Stage::Prediction), (3, Stage::Local), (5, Stage::Global), (7, Stage::Local)];
        let ticks = [100, 110, 130, 160, 200];
        let t = stage_times(&marks, &ticks, 2.0);
        assert!((t[Stage::Prediction] - 20e-9).abs() < 1e-15);
        assert!((t[Stage::Local] - (40e-9 + 80e-9)).abs() < 1e-15);
        assert!((t[Stage::Global] - 60e-9).abs() < 1e-15);
        assert_eq!(t[Stage::Damping], 0.0);
    }

    #[test]
    fn each_kernel_sums_its_dispatches_in_the_order_first_run() {
        let t = kernel_times(&["predict", "sweep", "reduce", "sweep"], &[0, 5, 15, 16, 26], 1.0);
        assert_eq!(t.iter().map(|e| e.0).collect::<Vec<_>>(), ["predict", "sweep", "reduce"]);
        assert!((t[1].1 - 20e-9).abs() < 1e-15 && (t[2].1 - 1e-9).abs() < 1e-15);
    }
}
