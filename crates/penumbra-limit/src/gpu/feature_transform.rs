//! The exact nearest-seed map on the GPU ([`crate::feature_transform`] on the CPU, step by step
//! in the same integer arithmetic): every texel of a buffer of seeds gets its nearest seed.

use super::pipelines::{FEATURE_TRANSFORM, FtParams};
use soft_shadow_core::GpuContext;
use soft_shadow_core::gpu::compute::bind_group;

/// The feature-transform pipelines; build once per context
/// (`ctx.cached(GpuFeatureTransform::new)`).
pub(crate) struct GpuFeatureTransform {
    layout: wgpu::BindGroupLayout,
    columns: wgpu::ComputePipeline,
    rows: wgpu::ComputePipeline,
    /// Bound as the keys where a transform has none (the shader then reads none).
    no_keys: wgpu::Buffer,
}

impl GpuFeatureTransform {
    /// Builds the pipelines.
    pub(crate) fn new(ctx: &GpuContext) -> Self {
        let p = ctx.program(&FEATURE_TRANSFORM);
        Self {
            layout: p.layouts[0].clone(),
            columns: p.compute(ctx, "ft_columns"),
            rows: p.compute(ctx, "ft_rows"),
            no_keys: ctx.storage_buffer("no keys", &[]),
        }
    }

    /// Records the transform of the seeds in `buffers[0]` (`resolution²` packed `u32`s, as
    /// [`soft_shadow_core::seeds::pack`] makes them, [`soft_shadow_core::seeds::NONE`] for no seed), which then holds
    /// every texel's nearest seed as [`crate::feature_transform::nearest`] gives it, ties to
    /// the least of `keys` (`resolution²` `f32`s) where given; `buffers[1]` (as large) is
    /// scratch. Two passes: one invocation per column, then one per row.
    pub(crate) fn encode(
        &self,
        ctx: &GpuContext,
        enc: &mut wgpu::CommandEncoder,
        buffers: [&wgpu::Buffer; 2],
        keys: Option<&wgpu::Buffer>,
        resolution: u32,
    ) {
        let prm = FtParams {
            resolution,
            keyed: keys.is_some() as u32,
            _pad: [0; 2],
        };
        let ub = ctx.uniform_buffer("feature transform", bytemuck::bytes_of(&prm));
        let bind = bind_group(
            ctx,
            "feature transform",
            &self.layout,
            &[
                ub.as_entire_binding(),
                buffers[0].as_entire_binding(),
                buffers[1].as_entire_binding(),
                keys.unwrap_or(&self.no_keys).as_entire_binding(),
            ],
        );
        for pipeline in [&self.columns, &self.rows] {
            let mut pass = ctx.begin_compute_pass(enc, "feature transform");
            pass.set_pipeline(pipeline);
            pass.set_bind_group(0, &bind, &[]);
            pass.dispatch_workgroups(resolution.div_ceil(64), 1, 1);
        }
    }
}
