//! The compiled stages (one compute pipeline per WGSL entry point, compiled once per device)
//! and the bind groups that tie them to a simulation's buffers (made again when the buffers or
//! the colour count change).

use super::buffers::Buffers;
use super::{
    attach, chebyshev, close_seams, coarse, contacts, finish, gauss_seidel, hash, mesh_hash, predict, project_stencils,
    project_triangles, ramp, resolve_mesh, self_collide,
};

pub(super) struct Pipelines {
    pub(super) predict: wgpu::ComputePipeline,
    pub(super) detect: wgpu::ComputePipeline,
    pub(super) project: wgpu::ComputePipeline,
    pub(super) project_stencils: wgpu::ComputePipeline,
    pub(super) gauss_seidel: wgpu::ComputePipeline,
    pub(super) reduce_partial: wgpu::ComputePipeline,
    pub(super) reduce: wgpu::ComputePipeline,
    pub(super) extrapolate: wgpu::ComputePipeline,
    pub(super) finish: wgpu::ComputePipeline,
    pub(super) ramp: wgpu::ComputePipeline,
    pub(super) mesh_lerp: wgpu::ComputePipeline,
    pub(super) mesh_count: wgpu::ComputePipeline,
    pub(super) mesh_scatter: wgpu::ComputePipeline,
    pub(super) scan_blocks: wgpu::ComputePipeline,
    pub(super) scan_sums: wgpu::ComputePipeline,
    pub(super) scan_apply: wgpu::ComputePipeline,
    pub(super) hash_sort: wgpu::ComputePipeline,
    pub(super) resolve_mesh: wgpu::ComputePipeline,
    pub(super) self_count: wgpu::ComputePipeline,
    pub(super) self_scatter: wgpu::ComputePipeline,
    pub(super) self_gather: wgpu::ComputePipeline,
    pub(super) self_apply: wgpu::ComputePipeline,
    pub(super) attach: wgpu::ComputePipeline,
    pub(super) gate: wgpu::ComputePipeline,
    pub(super) close_seams: wgpu::ComputePipeline,
    pub(super) coarse_residual: wgpu::ComputePipeline,
    pub(super) coarse_restrict: wgpu::ComputePipeline,
    pub(super) coarse_solve: wgpu::ComputePipeline,
    pub(super) coarse_prolong: wgpu::ComputePipeline,
    pub(super) coarse_prolong_history: wgpu::ComputePipeline,
}

pub(super) struct BindGroups {
    pub(super) predict: wgpu::BindGroup,
    pub(super) detect: wgpu::BindGroup,
    pub(super) project: wgpu::BindGroup,
    pub(super) project_stencils: wgpu::BindGroup,
    pub(super) gauss_seidel: Vec<wgpu::BindGroup>,
    pub(super) reduce_partial: wgpu::BindGroup,
    pub(super) reduce: wgpu::BindGroup,
    pub(super) extrapolate: wgpu::BindGroup,
    pub(super) finish: wgpu::BindGroup,
    pub(super) ramp: wgpu::BindGroup,
    pub(super) mesh_lerp: wgpu::BindGroup,
    pub(super) mesh_count: wgpu::BindGroup,
    pub(super) mesh_scatter: wgpu::BindGroup,
    pub(super) mesh_scan: [wgpu::BindGroup; 3],
    pub(super) mesh_sort: wgpu::BindGroup,
    pub(super) resolve_mesh: wgpu::BindGroup,
    pub(super) self_count: wgpu::BindGroup,
    pub(super) self_scatter: wgpu::BindGroup,
    pub(super) self_scan: [wgpu::BindGroup; 3],
    pub(super) self_sort: wgpu::BindGroup,
    pub(super) self_gather: wgpu::BindGroup,
    pub(super) self_apply: wgpu::BindGroup,
    pub(super) attach: wgpu::BindGroup,
    pub(super) gate: wgpu::BindGroup,
    pub(super) close_seams: wgpu::BindGroup,
    pub(super) coarse_residual: wgpu::BindGroup,
    pub(super) coarse_restrict: wgpu::BindGroup,
    pub(super) coarse_solve: wgpu::BindGroup,
    pub(super) coarse_prolong: wgpu::BindGroup,
    pub(super) coarse_prolong_history: wgpu::BindGroup,
}

impl Pipelines {
    /// Every stage compiled on `device`.
    pub(super) fn compile(device: &wgpu::Device) -> Self {
        Pipelines {
            predict: compile(device, "predict", predict::SOURCE, predict::ENTRY),
            detect: compile(device, "contacts", contacts::SOURCE, contacts::ENTRY),
            project: compile(device, "project_triangles", project_triangles::SOURCE, project_triangles::ENTRY),
            project_stencils: compile(device, "project_stencils", project_stencils::SOURCE, project_stencils::ENTRY),
            gauss_seidel: compile(device, "gauss_seidel", gauss_seidel::SOURCE, gauss_seidel::ENTRY),
            reduce_partial: compile(device, "reduce_partial", chebyshev::SOURCE, chebyshev::REDUCE_PARTIAL_ENTRY),
            reduce: compile(device, "reduce_omega", chebyshev::SOURCE, chebyshev::REDUCE_ENTRY),
            extrapolate: compile(device, "extrapolate", chebyshev::SOURCE, chebyshev::EXTRAPOLATE_ENTRY),
            finish: compile(device, "finish", finish::SOURCE, finish::ENTRY),
            ramp: compile(device, "ramp", ramp::SOURCE, ramp::ENTRY),
            mesh_lerp: compile(device, "mesh_lerp", mesh_hash::SOURCE, mesh_hash::LERP_ENTRY),
            attach: compile(device, "attach", attach::SOURCE, attach::ENTRY),
            gate: compile(device, "gate", chebyshev::SOURCE, chebyshev::GATE_ENTRY),
            close_seams: compile(device, "close_seams", close_seams::SOURCE, close_seams::ENTRY),
            mesh_count: compile(device, "mesh_count", mesh_hash::SOURCE, mesh_hash::COUNT_ENTRY),
            mesh_scatter: compile(device, "mesh_scatter", mesh_hash::SOURCE, mesh_hash::SCATTER_ENTRY),
            scan_blocks: compile(device, "scan_blocks", hash::SOURCE, hash::SCAN_BLOCKS_ENTRY),
            scan_sums: compile(device, "scan_sums", hash::SOURCE, hash::SCAN_SUMS_ENTRY),
            scan_apply: compile(device, "scan_apply", hash::SOURCE, hash::SCAN_APPLY_ENTRY),
            hash_sort: compile(device, "hash_sort", hash::SOURCE, hash::SORT_ENTRY),
            resolve_mesh: compile(device, "resolve_mesh", resolve_mesh::SOURCE, resolve_mesh::ENTRY),
            self_count: compile(device, "self_count", self_collide::SOURCE, self_collide::COUNT_ENTRY),
            self_scatter: compile(device, "self_scatter", self_collide::SOURCE, self_collide::SCATTER_ENTRY),
            self_gather: compile(device, "self_gather", self_collide::SOURCE, self_collide::GATHER_ENTRY),
            self_apply: compile(device, "self_apply", self_collide::SOURCE, self_collide::APPLY_ENTRY),
            coarse_residual: compile(device, "coarse_residual", coarse::SOURCE, coarse::RESIDUAL_ENTRY),
            coarse_restrict: compile(device, "coarse_restrict", coarse::SOURCE, coarse::RESTRICT_ENTRY),
            coarse_solve: compile(device, "coarse_solve", coarse::SOURCE, coarse::SOLVE_ENTRY),
            coarse_prolong: compile(device, "coarse_prolong", coarse::SOURCE, coarse::PROLONG_ENTRY),
            coarse_prolong_history: compile(
                device,
                "coarse_prolong_history",
                coarse::SOURCE,
                coarse::PROLONG_HISTORY_ENTRY,
            ),
        }
    }
}

impl BindGroups {
    /// The bind groups of every stage on buffers `b`, with `colours` Gauss-Seidel colour
    /// uniforms `stride` bytes apart in `b.colours`.
    pub(super) fn new(d: &wgpu::Device, pl: &Pipelines, b: &Buffers, colours: usize, stride: u64) -> Self {
        let gs_common = gauss_seidel::entries(b);
        let gauss_seidel = (0..colours)
            .map(|c| {
                let mut entries: Vec<wgpu::BindGroupEntry> = gs_common
                    .iter()
                    .map(|&(binding, buf)| wgpu::BindGroupEntry { binding, resource: buf.as_entire_binding() })
                    .collect();
                entries.push(wgpu::BindGroupEntry {
                    binding: 2,
                    resource: wgpu::BindingResource::Buffer(wgpu::BufferBinding {
                        buffer: &b.colours,
                        offset: c as u64 * stride,
                        size: wgpu::BufferSize::new(16),
                    }),
                });
                d.create_bind_group(&wgpu::BindGroupDescriptor {
                    label: Some("gauss_seidel colour"),
                    layout: &pl.gauss_seidel.get_bind_group_layout(0),
                    entries: &entries,
                })
            })
            .collect();
        let mesh_table =
            hash::Table { info: &b.mesh_table_info, counts: &b.mcounts, table: &b.mtable, block_sums: &b.mblocks };
        let self_table =
            hash::Table { info: &b.self_table_info, counts: &b.scounts, table: &b.stable, block_sums: &b.sblocks };
        BindGroups {
            predict: bind(d, &pl.predict, "predict", &predict::entries(b)),
            detect: bind(d, &pl.detect, "contacts", &contacts::entries(b)),
            project: bind(d, &pl.project, "project_triangles", &project_triangles::entries(b)),
            project_stencils: bind(d, &pl.project_stencils, "project_stencils", &project_stencils::entries(b)),
            gauss_seidel,
            reduce_partial: bind(d, &pl.reduce_partial, "reduce_partial", &chebyshev::reduce_partial_entries(b)),
            reduce: bind(d, &pl.reduce, "reduce_omega", &chebyshev::reduce_entries(b)),
            extrapolate: bind(d, &pl.extrapolate, "extrapolate", &chebyshev::extrapolate_entries(b)),
            finish: bind(d, &pl.finish, "finish", &finish::entries(b)),
            ramp: bind(d, &pl.ramp, "ramp", &ramp::entries(b)),
            mesh_lerp: bind(d, &pl.mesh_lerp, "mesh_lerp", &mesh_hash::lerp_entries(b)),
            mesh_count: bind(d, &pl.mesh_count, "mesh_count", &mesh_hash::count_entries(b)),
            mesh_scatter: bind(d, &pl.mesh_scatter, "mesh_scatter", &mesh_hash::scatter_entries(b)),
            mesh_scan: scan_groups(d, pl, "mesh_scan", &mesh_table),
            mesh_sort: bind(d, &pl.hash_sort, "mesh_sort", &mesh_table.sort_entries()),
            resolve_mesh: bind(d, &pl.resolve_mesh, "resolve_mesh", &resolve_mesh::entries(b)),
            self_count: bind(d, &pl.self_count, "self_count", &self_collide::count_entries(b)),
            self_scatter: bind(d, &pl.self_scatter, "self_scatter", &self_collide::scatter_entries(b)),
            self_scan: scan_groups(d, pl, "self_scan", &self_table),
            self_sort: bind(d, &pl.hash_sort, "self_sort", &self_table.sort_entries()),
            self_gather: bind(d, &pl.self_gather, "self_gather", &self_collide::gather_entries(b)),
            self_apply: bind(d, &pl.self_apply, "self_apply", &self_collide::apply_entries(b)),
            attach: bind(d, &pl.attach, "attach", &attach::entries(b)),
            gate: bind(d, &pl.gate, "gate", &chebyshev::gate_entries(b)),
            close_seams: bind(d, &pl.close_seams, "close_seams", &close_seams::entries(b)),
            coarse_residual: bind(d, &pl.coarse_residual, "coarse_residual", &coarse::residual_entries(b)),
            coarse_restrict: bind(d, &pl.coarse_restrict, "coarse_restrict", &coarse::restrict_entries(b)),
            coarse_solve: bind(d, &pl.coarse_solve, "coarse_solve", &coarse::solve_entries(b)),
            coarse_prolong: bind(d, &pl.coarse_prolong, "coarse_prolong", &coarse::prolong_entries(b)),
            coarse_prolong_history: bind(
                d,
                &pl.coarse_prolong_history,
                "coarse_prolong_history",
                &coarse::prolong_history_entries(b),
            ),
        }
    }
}

/// The three scan passes' bind groups for one table: blocks, sums, apply.
pub(super) fn scan_groups(d: &wgpu::Device, pl: &Pipelines, label: &str, t: &hash::Table) -> [wgpu::BindGroup; 3] {
    [
        bind(d, &pl.scan_blocks, label, &t.scan_blocks_entries()),
        bind(d, &pl.scan_sums, label, &t.scan_sums_entries()),
        bind(d, &pl.scan_apply, label, &t.scan_apply_entries()),
    ]
}

pub(super) fn compile(device: &wgpu::Device, label: &str, src: &str, entry: &str) -> wgpu::ComputePipeline {
    let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some(label),
        source: wgpu::ShaderSource::Wgsl(src.into()),
    });
    device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
        label: Some(label),
        layout: None,
        module: &module,
        entry_point: Some(entry),
        compilation_options: Default::default(),
        cache: None,
    })
}

pub(super) fn bind(
    device: &wgpu::Device,
    p: &wgpu::ComputePipeline,
    label: &str,
    e: &[(u32, &wgpu::Buffer)],
) -> wgpu::BindGroup {
    let entries: Vec<wgpu::BindGroupEntry> =
        e.iter().map(|&(binding, b)| wgpu::BindGroupEntry { binding, resource: b.as_entire_binding() }).collect();
    device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some(label),
        layout: &p.get_bind_group_layout(0),
        entries: &entries,
    })
}
