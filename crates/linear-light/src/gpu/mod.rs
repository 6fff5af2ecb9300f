//! The GPU path. Generation records everything in one command buffer:
//!
//! 1. one nearest-surface depth pass per sample (`soft_shadow_core`'s rasterizer) into a depth array;
//! 2. per sample, the quads of its map that hold a skin (`find_skins.wgsl`, appended with an
//!    atomic counter that doubles as an indirect draw's vertex count), then per sample the skins
//!    of each neighbour warped into its view (`skins.wgsl`, an indirect draw of those quads);
//! 3. the visibility channel from the warped values (`combine.wgsl`).
//!
//! Evaluation is `visibility()` in `visibility.wgsl`.

pub(crate) mod pipelines;

use crate::params::LinearLight;
use crate::samples::{lit_share, piece_share, sample_views};
use crate::segments::Segment;
use crate::skins::Unproject;
use bytemuck::{Pod, Zeroable};
use pipelines::{CombineKernel, FindSkinsKernel, SkinPipeline, VALUE_FORMAT};
use soft_shadow_core::gpu::Kernel;
use soft_shadow_core::gpu::compute::{bind_group, depth_array_view};
use soft_shadow_core::gpu::raster::{DEPTH_FORMAT, read_texture};
use soft_shadow_core::gpu::resources::texture_2d;
use soft_shadow_core::gpu::timer::PassSlot;
use soft_shadow_core::gpu::{GpuRasterizer, GpuScene};
use soft_shadow_core::raster::DepthPass;
use soft_shadow_core::{Bias, Generation, GpuContext, Map2D, MapParams, Result, ShadowError};

/// One sample as the shaders read it (`Sample` in `sample.wgsl`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub(crate) struct SampleGpu {
    /// The sample's map.
    pub map: MapParams,
    /// View to world.
    pub inv_view: [f32; 16],
    /// Projection scale in x.
    pub sx: f32,
    /// Projection scale in y.
    pub sy: f32,
    /// [`LinearLight::edge_threshold`].
    pub edge_threshold: f32,
    /// Share of one piece of the segment.
    pub piece: f32,
}

/// The maps of one linear light, kept on the GPU.
pub struct GpuLinearMaps {
    /// One entry per sample.
    pub(crate) samples: Vec<SampleGpu>,
    /// The depth maps, one layer per sample.
    pub(crate) depth: wgpu::Texture,
    /// The visibility channels, one R32Float layer per sample.
    pub(crate) channel: wgpu::Texture,
}

impl GpuLinearMaps {
    /// Reads the visibility channels back (tests).
    pub fn read_channels(&self, ctx: &GpuContext) -> Result<Vec<Map2D<f32>>> {
        let resolution = self.samples.first().map_or(0, |s| s.map.resolution);
        (0..self.samples.len() as u32)
            .map(|k| {
                let v: Vec<f32> = read_texture(ctx, &self.channel, k, wgpu::TextureAspect::All, 4)?;
                Map2D::from_vec(resolution, resolution, v)
                    .ok_or_else(|| ShadowError::Gpu("channel readback size".into()))
            })
            .collect()
    }
}

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
pub(crate) struct Pair {
    src: u32,
    dst: u32,
    _pad: [u32; 2],
}

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
pub(crate) struct CombineParams {
    layer: u32,
    has_prev: u32,
    has_next: u32,
    lit: f32,
    piece: f32,
    resolution: u32,
    _pad: [u32; 2],
}

/// Evaluation parameters (binding 0 of the maps' bind group), laid out as `EvalParams` in
/// `visibility.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub(crate) struct EvalParams {
    /// Receiver biases.
    pub bias: Bias,
    /// Number of samples (map layers).
    pub samples: u32,
    /// Padding to 16 bytes.
    pub _pad: [u32; 3],
}

/// Records the warp of sample `src`'s skins into sample `dst`'s view, into `value`.
#[allow(clippy::too_many_arguments)]
fn encode_warp(
    ctx: &GpuContext,
    enc: &mut wgpu::CommandEncoder,
    pipe: &SkinPipeline,
    samples: &wgpu::Buffer,
    depth_view: &wgpu::TextureView,
    value: &wgpu::TextureView,
    skin_depth: &wgpu::TextureView,
    list: &SkinList,
    src: u32,
    dst: u32,
) {
    let pair = Pair {
        src,
        dst,
        _pad: [0; 2],
    };
    let ub = ctx.uniform_buffer("skin pair", bytemuck::bytes_of(&pair));
    let bind = bind_group(
        ctx,
        "skins",
        &pipe.layout,
        &[
            ub.as_entire_binding(),
            samples.as_entire_binding(),
            wgpu::BindingResource::TextureView(depth_view),
            list.quads.as_entire_binding(),
        ],
    );
    let slot = ctx.pass_slot();
    let mut rp = enc.begin_render_pass(&wgpu::RenderPassDescriptor {
        label: Some("skins"),
        color_attachments: &[Some(wgpu::RenderPassColorAttachment {
            view: value,
            depth_slice: None,
            resolve_target: None,
            ops: wgpu::Operations {
                load: wgpu::LoadOp::Clear(wgpu::Color {
                    r: crate::warp::NO_SKIN as f64,
                    g: 0.0,
                    b: 0.0,
                    a: 0.0,
                }),
                store: wgpu::StoreOp::Store,
            },
        })],
        depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
            view: skin_depth,
            depth_ops: Some(wgpu::Operations {
                load: wgpu::LoadOp::Clear(0.0),
                store: wgpu::StoreOp::Store,
            }),
            stencil_ops: None,
        }),
        timestamp_writes: slot.as_ref().map(PassSlot::render_writes),
        occlusion_query_set: None,
        multiview_mask: None,
    });
    rp.set_pipeline(&pipe.pipeline);
    rp.set_bind_group(0, &bind, &[]);
    rp.draw_indirect(&list.draw, 0);
}

/// The skin quads of one sample's map and the indirect draw of them.
struct SkinList {
    /// Quad indices `y (resolution - 1) + x`.
    quads: wgpu::Buffer,
    /// `[vertex_count, instance_count, first_vertex, first_instance]`.
    draw: wgpu::Buffer,
}

/// Records `find_skins.wgsl` for sample `k`: its skin quads and their draw arguments.
#[allow(clippy::too_many_arguments)]
fn encode_find_skins(
    ctx: &GpuContext,
    enc: &mut wgpu::CommandEncoder,
    kernel: &Kernel,
    samples: &wgpu::Buffer,
    depth_view: &wgpu::TextureView,
    k: u32,
    resolution: u32,
) -> SkinList {
    let quads = ctx.buffer(&wgpu::BufferDescriptor {
        label: Some("skin quads"),
        size: 4 * (resolution as u64 - 1).pow(2).max(1),
        usage: wgpu::BufferUsages::STORAGE,
        mapped_at_creation: false,
    });
    let draw = ctx.buffer_with(
        "skin draw",
        bytemuck::cast_slice(&[0u32, 1, 0, 0]),
        wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::INDIRECT,
    );
    let pair = Pair {
        src: k,
        dst: k,
        _pad: [0; 2],
    };
    let ub = ctx.uniform_buffer("skin pair", bytemuck::bytes_of(&pair));
    let bind = bind_group(
        ctx,
        "find skins",
        &kernel.layout,
        &[
            ub.as_entire_binding(),
            samples.as_entire_binding(),
            wgpu::BindingResource::TextureView(depth_view),
            quads.as_entire_binding(),
            draw.as_entire_binding(),
        ],
    );
    let mut pass = ctx.begin_compute_pass(enc, "find skins");
    pass.set_pipeline(&kernel.pipeline);
    pass.set_bind_group(0, &bind, &[]);
    let g = resolution.saturating_sub(1).div_ceil(8).max(1);
    pass.dispatch_workgroups(g, g, 1);
    drop(pass);
    SkinList { quads, draw }
}

/// Records the maps of `segments` into `enc` (inputs already checked).
/// Layer `s N + i` holds sample `i` of segment `s`.
pub(crate) fn generate(
    ctx: &GpuContext,
    enc: &mut wgpu::CommandEncoder,
    t: &LinearLight,
    scene: &GpuScene,
    input: &Generation,
    segments: &[Segment],
) -> Result<GpuLinearMaps> {
    let resolution = input.resolution;
    let n = t.samples;
    let layers = n * segments.len() as u32;
    let raster = ctx.cached(GpuRasterizer::new);
    let skin_pipe = ctx.cached(SkinPipeline::new);
    let comb = ctx.cached(CombineKernel::new);
    let find = ctx.cached(FindSkinsKernel::new);
    let mut views = Vec::with_capacity(layers as usize);
    let mut samples = Vec::with_capacity(layers as usize);
    for seg in segments {
        let light = soft_shadow_core::Light::Linear { a: seg.a, b: seg.b };
        // The grid maps hold the receivers too: a cube face starts before the nearest of
        // either.
        let coverage = input.coverage_with_receivers_of(&light);
        for v in sample_views(seg.a, seg.b, n, seg.axis, &coverage, seg.weight) {
            let un = Unproject::new(&v.view, resolution);
            samples.push(SampleGpu {
                map: v.params(resolution),
                inv_view: un.inv_view.to_cols_array(),
                sx: un.sx,
                sy: un.sy,
                edge_threshold: t.edge_threshold_at(resolution),
                piece: seg.weight * piece_share(n),
            });
            views.push(v);
        }
    }
    let sb = ctx.storage_buffer("linear samples", bytemuck::cast_slice(&samples));
    let tris = scene.casters();
    let depth = GpuRasterizer::depth_array(ctx, resolution, layers)?;
    // Skins and their warps read the grid maps (casters and receivers, see `grid_geometry`).
    let surfaces = scene.surfaces(ctx)?;
    let grid_tris = &surfaces.0;
    let grid = GpuRasterizer::depth_array(ctx, resolution, layers)?;
    let grid_view = depth_array_view(&grid);
    let attach = wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING;
    let values =
        [0, 1].map(|_| texture_2d(ctx, "skin values", resolution, (1, 1), VALUE_FORMAT, attach));
    let skin_depth = texture_2d(
        ctx,
        "skin depth",
        resolution,
        (1, 1),
        DEPTH_FORMAT,
        wgpu::TextureUsages::RENDER_ATTACHMENT,
    );
    let channel = texture_2d(
        ctx,
        "visibility channels",
        resolution,
        (layers, 1),
        VALUE_FORMAT,
        wgpu::TextureUsages::STORAGE_BINDING
            | wgpu::TextureUsages::TEXTURE_BINDING
            | wgpu::TextureUsages::COPY_SRC,
    );
    let value_views = values
        .each_ref()
        .map(|v| v.create_view(&Default::default()));
    let skin_depth_view = skin_depth.create_view(&Default::default());
    let channel_view = channel.create_view(&wgpu::TextureViewDescriptor {
        dimension: Some(wgpu::TextureViewDimension::D2Array),
        ..Default::default()
    });
    for (k, v) in views.iter().enumerate() {
        for (t, target) in [(tris, &depth), (grid_tris, &grid)] {
            raster.encode_depth_pass(ctx, enc, t, &v.view, target, k as u32, DepthPass::NEAREST);
        }
    }
    let lists: Vec<SkinList> = (0..layers)
        .map(|k| encode_find_skins(ctx, enc, &find.0, &sb, &grid_view, k, resolution))
        .collect();
    for layer in 0..layers {
        // Sample `i` of segment `layer / N`; its neighbours are on the same segment.
        let (first, i) = (layer - layer % n, layer % n);
        let weight = segments[(layer / n) as usize].weight;
        let nbrs = [i.checked_sub(1), (i + 1 < n).then_some(i + 1)].map(|j| j.map(|j| first + j));
        for (slot, j) in nbrs.iter().enumerate() {
            if let Some(j) = j {
                encode_warp(
                    ctx,
                    enc,
                    &skin_pipe,
                    &sb,
                    &grid_view,
                    &value_views[slot],
                    &skin_depth_view,
                    &lists[*j as usize],
                    *j,
                    layer,
                );
            }
        }
        let cp = CombineParams {
            layer,
            has_prev: nbrs[0].is_some() as u32,
            has_next: nbrs[1].is_some() as u32,
            lit: weight * lit_share(i, n),
            piece: weight * piece_share(n),
            resolution,
            _pad: [0; 2],
        };
        let ub = ctx.uniform_buffer("linear combine", bytemuck::bytes_of(&cp));
        let bind = bind_group(
            ctx,
            "linear combine",
            &comb.0.layout,
            &[
                ub.as_entire_binding(),
                wgpu::BindingResource::TextureView(&value_views[0]),
                wgpu::BindingResource::TextureView(&value_views[1]),
                wgpu::BindingResource::TextureView(&channel_view),
            ],
        );
        let mut pass = ctx.begin_compute_pass(enc, "linear combine");
        pass.set_pipeline(&comb.0.pipeline);
        pass.set_bind_group(0, &bind, &[]);
        let g = resolution.div_ceil(8);
        pass.dispatch_workgroups(g, g, 1);
    }
    // Scratch back to the pool: the passes recorded above still run first.
    for texture in [grid, skin_depth].into_iter().chain(values) {
        ctx.recycle_texture(texture);
    }
    for list in lists {
        ctx.recycle_buffer(list.quads);
    }
    Ok(GpuLinearMaps {
        samples,
        depth,
        channel,
    })
}

/// The bind group of `maps` read with `t`'s biases.
pub(crate) fn bind_maps(
    ctx: &GpuContext,
    layout: &wgpu::BindGroupLayout,
    t: &LinearLight,
    maps: &GpuLinearMaps,
) -> wgpu::BindGroup {
    let prm = EvalParams {
        bias: t.bias,
        samples: maps.samples.len() as u32,
        _pad: [0; 3],
    };
    let ub = ctx.uniform_buffer("linear eval", bytemuck::bytes_of(&prm));
    let sb = ctx.storage_buffer("linear samples", bytemuck::cast_slice(&maps.samples));
    let depth_view = depth_array_view(&maps.depth);
    let channel_view = maps.channel.create_view(&wgpu::TextureViewDescriptor {
        dimension: Some(wgpu::TextureViewDimension::D2Array),
        ..Default::default()
    });
    bind_group(
        ctx,
        "linear evaluate",
        layout,
        &[
            ub.as_entire_binding(),
            sb.as_entire_binding(),
            wgpu::BindingResource::TextureView(&depth_view),
            wgpu::BindingResource::TextureView(&channel_view),
        ],
    )
}
