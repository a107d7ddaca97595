//! A frame's plan: every compute dispatch of one GPU frame, in order, as a list.
//!
//! The frame records exactly this list into one compute pass, and the dispatch count that
//! benchmarks and the step statistics report is this list's length, so the count is never
//! kept by hand beside the recording (it had drifted: new stages were recorded but not
//! counted). Per substep, the stages of the CPU's substep in its order:
//!
//! 1. `close_seams` (while pairs were on their closing schedule at upload), `predict`; when the colliders' hash is rebuilt (every substep while one moves, else once
//!    after an upload) `lerp`, `count`, `scan` (three passes), `scatter`, `sort`; `attach` (riding pins);
//! 2. per iteration: `gate` (early stop on, from the second iteration), `detect` (colliders),
//!    `project` (triangles), `project_stencils` (curved), `gauss_seidel` (one per colour),
//!    `reduce_partial` and `reduce_omega`, `extrapolate` (Chebyshev), the two-level step's
//!    coarse correction (`coarse_residual`, `coarse_restrict`, `coarse_solve`,
//!    `coarse_prolong`), the self-collision
//!    passes (count, scan in three, scatter, sort, gather, apply);
//! 3. `resolve_mesh` (mesh colliders), `finish`, `ramp`.

use super::{
    attach, chebyshev, coarse, contacts, gauss_seidel, groups, hash, mesh_hash, predict, project_stencils,
    project_triangles, resolve_mesh, self_collide, BindGroups, Method, Pipelines, Uploaded,
};
use crate::solver::Stage;

/// One dispatch: a stage's pipeline, its bind group, the workgroups to launch, the CPU
/// step's stage it belongs to (for the per-stage times the GPU's timestamps give) and its
/// kernel's name (for the per-kernel times of a profile, `GpuSolver::set_kernel_timing`).
pub(super) struct Dispatch<'a> {
    pub pipeline: &'a wgpu::ComputePipeline,
    pub bind: &'a wgpu::BindGroup,
    pub groups: u32,
    pub stage: Stage,
    pub kernel: &'static str,
}

/// Timestamp marks for a frame's plan: the first is before the first dispatch, and one
/// follows each run of dispatches of one stage (the run's stage). Times per stage are the
/// differences between successive marks.
pub(super) fn stage_marks(plan: &[Dispatch<'_>]) -> Vec<(usize, Stage)> {
    let mut marks = Vec::new();
    for (k, d) in plan.iter().enumerate() {
        if plan.get(k + 1).is_none_or(|next| next.stage != d.stage) {
            marks.push((k, d.stage));
        }
    }
    marks
}

/// Timestamp marks for a profile: one after every dispatch, so that each interval is one
/// kernel's (`Dispatch::kernel`) time.
pub(super) fn kernel_marks(plan: &[Dispatch<'_>]) -> Vec<(usize, Stage)> {
    plan.iter().enumerate().map(|(k, d)| (k, d.stage)).collect()
}

/// The three passes of a table's scan (`hash.wgsl`): pipeline, bind group, workgroups.
fn scan<'a>(
    pl: &'a Pipelines,
    groups: &'a [wgpu::BindGroup; 3],
    buckets: usize,
) -> [(&'a wgpu::ComputePipeline, &'a wgpu::BindGroup, u32); 3] {
    let blocks = hash::scan_blocks(buckets) as u32;
    [(&pl.scan_blocks, &groups[0], blocks), (&pl.scan_sums, &groups[1], 1), (&pl.scan_apply, &groups[2], blocks)]
}

/// The dispatches of one frame of `substeps` × `iterations` for the uploaded scene `u`;
/// `rebuild_each_substep`: a collider moves (its hash is rebuilt every substep), else
/// `rebuild_first`: built once, in the first substep.
pub(super) fn frame<'a>(
    pl: &'a Pipelines,
    g: &'a BindGroups,
    u: &Uploaded,
    substeps: u32,
    iterations: u32,
    rebuild_each_substep: bool,
    mut rebuild_first: bool,
) -> Vec<Dispatch<'a>> {
    let n = u.n;
    // Each dispatch counts in the stage the CPU times the same work in (`Simulation::substep`
    // and `iterate`: contacts and projections are the local stage; the sweep, Chebyshev and
    // self-collision the global one; resolve, velocities and the ramp the damping stage).
    let stage = std::cell::Cell::new(Stage::Prediction);
    let mut plan = Vec::new();
    let mut add =
        |kernel, pipeline, bind, groups| plan.push(Dispatch { pipeline, bind, groups, stage: stage.get(), kernel });
    for _ in 0..substeps {
        stage.set(Stage::Prediction);
        if u.closing_scheduled {
            // Before `predict`, as `Simulation::predict` closes the seams first.
            add("close_seams", &pl.close_seams, &g.close_seams, 1);
        }
        add("predict", &pl.predict, &g.predict, groups(n, predict::WORKGROUP));
        if rebuild_each_substep || rebuild_first {
            rebuild_first = false;
            let wg = mesh_hash::WORKGROUP;
            add("mesh_lerp", &pl.mesh_lerp, &g.mesh_lerp, groups(u.n_mesh_verts, wg));
            add("mesh_count", &pl.mesh_count, &g.mesh_count, groups(u.n_mesh_tris, wg));
            for (p, b, n) in scan(pl, &g.mesh_scan, u.mesh_buckets) {
                add("mesh_scan", p, b, n);
            }
            add("mesh_scatter", &pl.mesh_scatter, &g.mesh_scatter, groups(u.n_mesh_tris, wg));
            add("mesh_sort", &pl.hash_sort, &g.mesh_sort, groups(u.mesh_buckets, hash::WORKGROUP));
        }
        if u.n_attach > 0 {
            // After `lerp`: the targets at this substep's collider positions.
            add("attach", &pl.attach, &g.attach, groups(u.n_attach, attach::WORKGROUP));
        }
        for k in 0..iterations {
            stage.set(Stage::Local);
            if u.early_stop && k > 0 {
                add("gate", &pl.gate, &g.gate, 1);
            }
            if u.n_colliders > 0 || u.n_meshes > 0 {
                add("detect", &pl.detect, &g.detect, groups(n, contacts::WORKGROUP));
            }
            add("project", &pl.project, &g.project, groups(u.n_tris, project_triangles::WORKGROUP));
            if u.n_curved > 0 {
                add(
                    "project_stencils",
                    &pl.project_stencils,
                    &g.project_stencils,
                    groups(u.n_curved, project_stencils::WORKGROUP),
                );
            }
            stage.set(Stage::Global);
            for (c, range) in u.colours.iter().enumerate() {
                add(
                    "gauss_seidel",
                    &pl.gauss_seidel,
                    &g.gauss_seidel[c],
                    groups(range.count as usize, gauss_seidel::WORKGROUP),
                );
            }
            add("reduce", &pl.reduce_partial, &g.reduce_partial, chebyshev::reduce_groups(n));
            add("reduce", &pl.reduce, &g.reduce, 1);
            if u.method == Method::Chebyshev {
                add("extrapolate", &pl.extrapolate, &g.extrapolate, groups(n, chebyshev::WORKGROUP));
            }
            if u.n_coarse > 0 {
                let wg = coarse::WORKGROUP;
                add("coarse_residual", &pl.coarse_residual, &g.coarse_residual, groups(n, wg));
                add("coarse_restrict", &pl.coarse_restrict, &g.coarse_restrict, groups(u.n_coarse, wg));
                add("coarse_solve", &pl.coarse_solve, &g.coarse_solve, 1);
                // With Chebyshev the corrected iterate is also the next iteration's history.
                if u.method == Method::Chebyshev {
                    add("coarse_prolong", &pl.coarse_prolong_history, &g.coarse_prolong_history, groups(n, wg));
                } else {
                    add("coarse_prolong", &pl.coarse_prolong, &g.coarse_prolong, groups(n, wg));
                }
            }
            if u.self_enabled {
                let wg = self_collide::WORKGROUP;
                add("self_count", &pl.self_count, &g.self_count, groups(n, wg));
                for (p, b, n) in scan(pl, &g.self_scan, u.self_buckets) {
                    add("self_scan", p, b, n);
                }
                add("self_scatter", &pl.self_scatter, &g.self_scatter, groups(n, wg));
                add("self_sort", &pl.hash_sort, &g.self_sort, groups(u.self_buckets, hash::WORKGROUP));
                add("self_gather", &pl.self_gather, &g.self_gather, groups(n, wg));
                add("self_apply", &pl.self_apply, &g.self_apply, groups(n, wg));
            }
        }
        stage.set(Stage::Damping);
        if u.n_meshes > 0 {
            add("resolve_mesh", &pl.resolve_mesh, &g.resolve_mesh, groups(n, resolve_mesh::WORKGROUP));
        }
        add("finish", &pl.finish, &g.finish, groups(n, super::finish::WORKGROUP));
        add("ramp", &pl.ramp, &g.ramp, 1);
    }
    plan
}
