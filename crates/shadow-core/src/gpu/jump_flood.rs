//! Jump flooding on the GPU ([`crate::jump_flood`] on the CPU): floods a buffer of packed seeds
//! so that every texel holds its nearest seed.

use super::GpuContext;
use super::compute::{bind_group, compute_pipelines, storage_entry, uniform_entry};
use super::resources::layout;
use bytemuck::{Pod, Zeroable};

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct FloodParams {
    res: u32,
    step: u32,
    _pad: [u32; 2],
}

/// The jump-flood pipeline; build once per context (`ctx.cached(GpuJumpFlood::new)`).
pub struct GpuJumpFlood {
    layout: wgpu::BindGroupLayout,
    pipeline: wgpu::ComputePipeline,
}

/// `jump_flood.wgsl`, for the resolver.
const JUMP_FLOOD_WGSL: &[(&str, &str)] = &[("jump_flood.wgsl", include_str!("jump_flood.wgsl"))];

impl GpuJumpFlood {
    /// Builds the pipeline.
    pub fn new(ctx: &GpuContext) -> Self {
        let source = super::wgsl::source("jump_flood.wgsl", JUMP_FLOOD_WGSL);
        let module = super::resources::wgsl_module(ctx, "jump flood", &[&source]);
        let layout = layout(
            ctx,
            "jump flood",
            &[
                uniform_entry(0),
                storage_entry(1, true),
                storage_entry(2, false),
            ],
        );
        let [pipeline] = compute_pipelines(ctx, "jump flood", &module, &layout, ["jfa_step"]);
        Self { layout, pipeline }
    }

    /// Records the flood of the seeds in `buffers[0]` (`resolution²` packed `u32`s, as
    /// [`crate::seeds::pack`] makes them, `u32::MAX` for no seed), ping-ponging with
    /// `buffers[1]`, with the steps [`crate::jump_flood::flood`] takes; returns the index of the
    /// buffer that holds every texel's nearest seed.
    pub fn encode(
        &self,
        ctx: &GpuContext,
        enc: &mut wgpu::CommandEncoder,
        buffers: [&wgpu::Buffer; 2],
        resolution: u32,
    ) -> usize {
        let groups = resolution.div_ceil(8);
        let mut cur = 0;
        for step in crate::jump_flood::steps(resolution) {
            let prm = FloodParams {
                res: resolution,
                step,
                _pad: [0; 2],
            };
            let ub = ctx.uniform_buffer("jump flood", bytemuck::bytes_of(&prm));
            let bind = bind_group(
                ctx,
                "jump flood",
                &self.layout,
                &[
                    ub.as_entire_binding(),
                    buffers[cur].as_entire_binding(),
                    buffers[1 - cur].as_entire_binding(),
                ],
            );
            let mut pass = ctx.begin_compute_pass(enc, "jump flood");
            pass.set_pipeline(&self.pipeline);
            pass.set_bind_group(0, &bind, &[]);
            pass.dispatch_workgroups(groups, groups, 1);
            cur = 1 - cur;
        }
        cur
    }
}
