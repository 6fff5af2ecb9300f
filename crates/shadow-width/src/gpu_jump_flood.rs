//! Jump flooding on the GPU ([`crate::jump_flood`] on the CPU): floods a buffer of packed seeds
//! so that every texel holds its nearest seed.

use crate::shaders::{FloodParams, JUMP_FLOOD};
use soft_shadow_core::GpuContext;
use soft_shadow_core::gpu::Kernel;
use soft_shadow_core::gpu::compute::bind_group;

/// The jump-flood pipeline; build once per context (`ctx.cached(GpuJumpFlood::new)`).
pub(crate) struct GpuJumpFlood {
    kernel: Kernel,
}

impl GpuJumpFlood {
    /// Builds the pipeline.
    pub(crate) fn new(ctx: &GpuContext) -> Self {
        Self {
            kernel: Kernel::new(ctx, &JUMP_FLOOD, "jfa_step"),
        }
    }

    /// Records the flood of the seeds in `buffers[0]` (`resolution²` packed `u32`s, as
    /// [`soft_shadow_core::seeds::pack`] makes them, `u32::MAX` for no seed), ping-ponging with
    /// `buffers[1]`, with the steps [`crate::jump_flood::flood`] takes; returns the index of the
    /// buffer that holds every texel's nearest seed.
    pub(crate) fn encode(
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
                resolution,
                step,
                _pad: [0; 2],
            };
            let ub = ctx.uniform_buffer("jump flood", bytemuck::bytes_of(&prm));
            let bind = bind_group(
                ctx,
                "jump flood",
                &self.kernel.layout,
                &[
                    ub.as_entire_binding(),
                    buffers[cur].as_entire_binding(),
                    buffers[1 - cur].as_entire_binding(),
                ],
            );
            let mut pass = ctx.begin_compute_pass(enc, "jump flood");
            pass.set_pipeline(&self.kernel.pipeline);
            pass.set_bind_group(0, &bind, &[]);
            pass.dispatch_workgroups(groups, groups, 1);
            cur = 1 - cur;
        }
        cur
    }
}
