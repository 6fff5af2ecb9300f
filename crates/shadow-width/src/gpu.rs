//! The GPU path: depth passes into one depth array (layer 0 nearest caster, 1 nearest back
//! face when asked for), the width map by the compute kernels of `width.wgsl`, and evaluation by
//! `visibility.wgsl`. Nothing is read back between generation steps.

use crate::attenuation::{AttenuationTable, FalloffKind};
use crate::eval::EvalParams;
use crate::gpu_jump_flood::GpuJumpFlood;
use crate::params::{DEFAULT_TABLE_SIZE, DepthLayer, Neighbours, ShadowWidth, WidthMethod};
use crate::shaders::{WIDTH, WidthParams};
use crate::width::{cap, propagate};
use soft_shadow_core::gpu::compute::{bind_group, depth_array_view};
use soft_shadow_core::gpu::resources::storage_buffer;
use soft_shadow_core::gpu::{GpuRasterizer, GpuScene};
use soft_shadow_core::raster::DepthPass;
use soft_shadow_core::{Generation, GpuContext, Map2D, MapParams, Result, SampleView, ShadowError};

/// The maps of one light, kept on the GPU.
pub struct GpuWidthMaps {
    /// Its shader-side parameters.
    pub(crate) params: MapParams,
    /// `Depth32Float` array: nearest caster, and (back-face depth) nearest back face.
    pub(crate) depth: wgpu::Texture,
    /// Shadow width in texels, `array<f32>` of `resolution²`.
    pub(crate) width: wgpu::Buffer,
    /// [`crate::params::softness_size`] of the light: its size over the fit factor.
    pub(crate) light_size: f32,
    /// Whether the light is a sphere, whose softness grows off the map's axis
    /// ([`soft_shadow_core::light_space::sphere_spread_at`]).
    pub(crate) sphere: bool,
}

impl GpuWidthMaps {
    /// Reads the width map back (tests, reports).
    pub fn read_width(&self, ctx: &GpuContext) -> Result<Map2D<f32>> {
        let resolution = self.params.resolution;
        let bytes = ctx.read_buffer(&self.width, resolution as u64 * resolution as u64 * 4)?;
        Map2D::from_vec(resolution, resolution, bytemuck::pod_collect_to_vec(&bytes))
            .ok_or_else(|| ShadowError::Gpu("width map readback size".into()))
    }
}

struct WidthPipelines {
    layout: wgpu::BindGroupLayout,
    mask: wgpu::ComputePipeline,
    propagate: wgpu::ComputePipeline,
    cap: wgpu::ComputePipeline,
    jfa_init: wgpu::ComputePipeline,
    jfa_resolve: wgpu::ComputePipeline,
    edt_columns: wgpu::ComputePipeline,
    edt_rows: wgpu::ComputePipeline,
}

impl WidthPipelines {
    fn new(ctx: &GpuContext) -> Self {
        let p = ctx.program(&WIDTH);
        Self {
            layout: p.layouts[0].clone(),
            mask: p.compute(ctx, "mask"),
            propagate: p.compute(ctx, "propagate"),
            cap: p.compute(ctx, "cap_width"),
            jfa_init: p.compute(ctx, "jfa_init"),
            jfa_resolve: p.compute(ctx, "jfa_resolve"),
            edt_columns: p.compute(ctx, "edt_columns"),
            edt_rows: p.compute(ctx, "edt_rows"),
        }
    }
}

/// One dispatch of the width kernels: pipeline, step, and the buffers in bindings 2..=7.
struct Dispatch<'a> {
    pipeline: &'a wgpu::ComputePipeline,
    step: u32,
    buffers: [&'a wgpu::Buffer; 6],
    lines: bool,
}

/// What every width dispatch shares: the pipelines, the depth layers and the parameters.
struct Kernels<'a> {
    ctx: &'a GpuContext,
    pipes: &'a WidthPipelines,
    depth_view: &'a wgpu::TextureView,
    params: WidthParams,
    /// The propagation's neighbourhood, for [`WidthMethod::Propagate`].
    neighbours: Option<Neighbours>,
}

impl Kernels<'_> {
    fn run(&self, enc: &mut wgpu::CommandEncoder, d: &Dispatch) {
        let resolution = self.params.resolution;
        let mut wp = WidthParams {
            step: d.step,
            ..self.params
        };
        if let (Some(n), true) = (self.neighbours, d.step > 0) {
            for (o, (dx, dy, len)) in wp.offsets.iter_mut().zip(propagate::offsets(n, d.step)) {
                *o = [dx as f32, dy as f32, len, 0.0];
            }
        }
        let ub = self
            .ctx
            .uniform_buffer("width params", bytemuck::bytes_of(&wp));
        let mut resources: Vec<wgpu::BindingResource> = vec![
            ub.as_entire_binding(),
            wgpu::BindingResource::TextureView(self.depth_view),
        ];
        resources.extend(d.buffers.iter().map(|b| b.as_entire_binding()));
        let bind = bind_group(self.ctx, "shadow width", &self.pipes.layout, &resources);
        let mut pass = self.ctx.begin_compute_pass(enc, "shadow width");
        pass.set_pipeline(d.pipeline);
        pass.set_bind_group(0, &bind, &[]);
        if d.lines {
            pass.dispatch_workgroups(resolution.div_ceil(64), 1, 1);
        } else {
            let g = resolution.div_ceil(8);
            pass.dispatch_workgroups(g, g, 1);
        }
    }
}

/// Records the depth layers and the width map into `enc` (inputs already checked).
pub(crate) fn generate(
    ctx: &GpuContext,
    enc: &mut wgpu::CommandEncoder,
    t: &ShadowWidth,
    scene: &GpuScene,
    input: &Generation,
) -> Result<GpuWidthMaps> {
    let (light, resolution) = (input.light, input.resolution);
    let raster = ctx.cached(GpuRasterizer::new);
    let pipes = ctx.cached(WidthPipelines::new);
    let view = SampleView::center(light, &input.coverage());
    let params = view.params(resolution);
    let texels = resolution as u64 * resolution as u64;
    let tris = scene.casters();
    let mut passes = vec![DepthPass::NEAREST];
    if t.depth == DepthLayer::BackFaces {
        passes.push(DepthPass::NEAREST_BACK);
    }
    let depth = GpuRasterizer::depth_array(ctx, resolution, passes.len() as u32)?;
    for (layer, pass) in passes.iter().enumerate() {
        raster.encode_depth_pass(ctx, enc, tris, &view.view, &depth, layer as u32, *pass);
    }
    let f = [
        storage_buffer(ctx, "width a", texels * 4),
        storage_buffer(ctx, "width b", texels * 4),
    ];
    let jfa_bytes = if t.method == WidthMethod::JumpFlood {
        texels * 4
    } else {
        4
    };
    let u = [
        storage_buffer(ctx, "seeds a", jfa_bytes),
        storage_buffer(ctx, "seeds b", jfa_bytes),
    ];
    let (v_bytes, z_bytes) = if t.method == WidthMethod::Exact {
        (texels * 4, (texels + resolution as u64) * 4)
    } else {
        (4, 4)
    };
    let env = [
        storage_buffer(ctx, "envelope v", v_bytes),
        storage_buffer(ctx, "envelope z", z_bytes),
    ];
    let neighbours = match t.method {
        WidthMethod::Propagate { neighbours } => Some(neighbours),
        _ => None,
    };
    let depth_view = depth_array_view(&depth);
    let kernels = Kernels {
        ctx,
        pipes: &pipes,
        depth_view: &depth_view,
        params: WidthParams {
            map: params,
            resolution,
            step: 0,
            neighbours: neighbours.map_or(0, Neighbours::count),
            cap: cap(resolution),
            offsets: [[0.0; 4]; 8],
        },
        neighbours,
    };
    // Ping-pong: every dispatch reads `src` and writes `dst` of each pair.
    let fw = |src: usize| [&f[src], &f[1 - src], &u[0], &u[1], &env[0], &env[1]];
    kernels.run(
        enc,
        &Dispatch {
            pipeline: &pipes.mask,
            step: 0,
            buffers: [&f[1], &f[0], &u[0], &u[1], &env[0], &env[1]],
            lines: false,
        },
    );
    let mut cur = 0; // f[cur] holds the latest f32 map
    match t.method {
        WidthMethod::Propagate { .. } => {
            for step in propagate::steps(resolution) {
                let d = Dispatch {
                    pipeline: &pipes.propagate,
                    step,
                    buffers: fw(cur),
                    lines: false,
                };
                kernels.run(enc, &d);
                cur = 1 - cur;
            }
            let d = Dispatch {
                pipeline: &pipes.cap,
                step: 0,
                buffers: fw(cur),
                lines: false,
            };
            kernels.run(enc, &d);
            cur = 1 - cur;
        }
        WidthMethod::JumpFlood => {
            // Seeds into u[0], flooded by soft_shadow_core's kernel, resolved to distances.
            let init = Dispatch {
                pipeline: &pipes.jfa_init,
                step: 0,
                buffers: [&f[cur], &f[1 - cur], &u[1], &u[0], &env[0], &env[1]],
                lines: false,
            };
            kernels.run(enc, &init);
            let flood = ctx.cached(GpuJumpFlood::new);
            let ucur = flood.encode(ctx, enc, [&u[0], &u[1]], resolution);
            let resolve = Dispatch {
                pipeline: &pipes.jfa_resolve,
                step: 0,
                buffers: [
                    &f[cur],
                    &f[1 - cur],
                    &u[ucur],
                    &u[1 - ucur],
                    &env[0],
                    &env[1],
                ],
                lines: false,
            };
            kernels.run(enc, &resolve);
            cur = 1 - cur;
        }
        WidthMethod::Exact => {
            for pipeline in [&pipes.edt_columns, &pipes.edt_rows] {
                let d = Dispatch {
                    pipeline,
                    step: 0,
                    buffers: fw(cur),
                    lines: true,
                };
                kernels.run(enc, &d);
                cur = 1 - cur;
            }
        }
    }
    // Scratch back to the pool: the passes recorded above still run first.
    let [a, b] = f;
    let (width, other) = if cur == 0 { (a, b) } else { (b, a) };
    for scratch in [other].into_iter().chain(u).chain(env) {
        ctx.recycle_buffer(scratch);
    }
    Ok(GpuWidthMaps {
        params,
        depth,
        width,
        light_size: crate::params::softness_size(light),
        sphere: matches!(light, soft_shadow_core::Light::Sphere { .. }),
    })
}

/// The bind group of `maps` read with `t`'s falloff and biases.
pub(crate) fn bind_maps(
    ctx: &GpuContext,
    layout: &wgpu::BindGroupLayout,
    t: &ShadowWidth,
    maps: &GpuWidthMaps,
) -> wgpu::BindGroup {
    let table_size = match (&t.falloff, t.table) {
        (_, Some(n)) => Some(n),
        (FalloffKind::Custom(_), None) => Some(DEFAULT_TABLE_SIZE),
        (FalloffKind::Linear { .. }, None) => None,
    };
    let table = table_size.map(|n| AttenuationTable::new(&t.falloff, n));
    let prm = EvalParams::new(
        t,
        maps.params,
        maps.light_size,
        maps.sphere,
        table.as_ref().map_or(0, |t| t.values.len() as u32),
    );
    let values = table.map_or(vec![1.0f32; 2], |t| t.values);
    let ub = ctx.uniform_buffer("shadow width eval", bytemuck::bytes_of(&prm));
    let tb = ctx.storage_buffer("attenuation table", bytemuck::cast_slice(&values));
    let dv = depth_array_view(&maps.depth);
    bind_group(
        ctx,
        "shadow width eval",
        layout,
        &[
            ub.as_entire_binding(),
            wgpu::BindingResource::TextureView(&dv),
            maps.width.as_entire_binding(),
            tb.as_entire_binding(),
        ],
    )
}
