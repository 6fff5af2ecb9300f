//! The GPU path. Generation records everything in one command buffer and reads nothing back:
//!
//! 1. the nearest-surface depth map (`soft_shadow_core`'s rasterizer), normalised into the geometry
//!    layer (`depth_image.wgsl`, `geometry`);
//! 2. the edge `[c, p_i]` and lower-limit layers, either by silhouette extrusion (render passes
//!    of `silhouette.wgsl`: ribbons with the penumbra limit as depth, then back faces) or from
//!    the depth image (`seeds`, two nearest-seed maps, `limits`);
//! 3. the stored map (`combine.wgsl`, written through a storage texture of the map's format).
//!
//! Evaluation is `visibility()` in `visibility.wgsl`.

pub(crate) mod feature_transform;
pub(crate) mod pipelines;

use crate::eval::EvalParams;
use crate::params::{Generator, PenumbraLimit};
use crate::silhouette::{Edge, edges};
use crate::storage::{Storage, Texel};
use crate::table::IlluminationTable;
use crate::warp::{NONE_DEPTH, Warp};
use bytemuck::{Pod, Zeroable};
use feature_transform::GpuFeatureTransform;
use pipelines::{
    CombinePipelines, DepthImagePipelines, EDGE_FORMAT, LOWER_FORMAT, SilhouettePipelines,
};
use soft_shadow_core::gpu::compute::{self, bind_group, depth_array_view};
use soft_shadow_core::gpu::raster::{DEPTH_FORMAT, read_texture};
use soft_shadow_core::gpu::resources::{storage_buffer, texture_2d};
use soft_shadow_core::gpu::timer::PassSlot;
use soft_shadow_core::gpu::{GpuRasterizer, GpuScene};
use soft_shadow_core::raster::DepthPass;
use soft_shadow_core::{
    Generation, GpuContext, Map2D, MapParams, Result, SampleView, SceneGeometry, ShadowError,
};

/// The penumbra limit map of one light, kept on the GPU.
pub struct GpuPenumbraMaps {
    /// Its shader-side parameters.
    pub(crate) params: MapParams,
    /// Depth warp and normalisation.
    pub(crate) warp: Warp,
    /// The map: raw channels `(c, g, b, p_i / 4 + 1/2)` in the storage format.
    pub(crate) map: wgpu::Texture,
    /// The storage format of `map`.
    pub(crate) storage: Storage,
    /// The visibility-to-illumination table for the light.
    pub(crate) table: IlluminationTable,
}

impl GpuPenumbraMaps {
    /// Reads the map back, decoded (tests, reports).
    pub fn read_map(&self, ctx: &GpuContext) -> Result<Map2D<Texel>> {
        let all = wgpu::TextureAspect::All;
        let raw: Vec<[f32; 4]> = match self.storage {
            Storage::F32 => read_texture(ctx, &self.map, 0, all, 16)?,
            Storage::F16 => read_texture::<[u16; 4]>(ctx, &self.map, 0, all, 8)?
                .iter()
                .map(|t| t.map(|h| half::f16::from_bits(h).to_f32()))
                .collect(),
            Storage::Rgba8 => read_texture::<[u8; 4]>(ctx, &self.map, 0, all, 4)?
                .iter()
                .map(|t| t.map(|b| b as f32 / 255.0))
                .collect(),
        };
        let resolution = self.params.resolution;
        Map2D::from_vec(
            resolution,
            resolution,
            raw.into_iter().map(Texel::decode).collect(),
        )
        .ok_or_else(|| ShadowError::Gpu("penumbra map readback size".into()))
    }
}

/// Generation parameters, laid out as `GenParams` in `warp.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
pub(crate) struct GenParams {
    map: MapParams,
    warp: Warp,
    resolution: u32,
    layer_gap: f32,
    transition_gap: f32,
    _pad: f32,
}

fn layer_usage() -> wgpu::TextureUsages {
    wgpu::TextureUsages::RENDER_ATTACHMENT
        | wgpu::TextureUsages::STORAGE_BINDING
        | wgpu::TextureUsages::TEXTURE_BINDING
        | wgpu::TextureUsages::COPY_SRC
}

/// One 8x8-workgroup dispatch over a `resolution²` map.
fn dispatch(
    ctx: &GpuContext,
    enc: &mut wgpu::CommandEncoder,
    pipeline: &wgpu::ComputePipeline,
    bind: &wgpu::BindGroup,
    resolution: u32,
) {
    let g = resolution.div_ceil(8);
    compute::dispatch(ctx, enc, "penumbra limit", pipeline, bind, (g, g, 1));
}

/// A render pass into `color` (cleared to `clear`) with depth `depth` cleared to `clear_depth`.
fn render_pass<'a>(
    ctx: &GpuContext,
    enc: &'a mut wgpu::CommandEncoder,
    label: &str,
    color: &'a wgpu::TextureView,
    clear: wgpu::Color,
    depth: &'a wgpu::TextureView,
    clear_depth: f32,
) -> wgpu::RenderPass<'a> {
    let slot = ctx.pass_slot();
    enc.begin_render_pass(&wgpu::RenderPassDescriptor {
        label: Some(label),
        color_attachments: &[Some(wgpu::RenderPassColorAttachment {
            view: color,
            depth_slice: None,
            resolve_target: None,
            ops: wgpu::Operations {
                load: wgpu::LoadOp::Clear(clear),
                store: wgpu::StoreOp::Store,
            },
        })],
        depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
            view: depth,
            depth_ops: Some(wgpu::Operations {
                load: wgpu::LoadOp::Clear(clear_depth),
                store: wgpu::StoreOp::Store,
            }),
            stencil_ops: None,
        }),
        timestamp_writes: slot.as_ref().map(PassSlot::render_writes),
        occlusion_query_set: None,
        multiview_mask: None,
    })
}

/// The casters' silhouette candidates ([`edges`]) on the GPU, derived once per scene.
struct GpuEdges {
    buffer: wgpu::Buffer,
    count: u32,
}

impl GpuEdges {
    fn new(ctx: &GpuContext, geometry: &SceneGeometry) -> Self {
        let mut data = edges(&geometry.casters);
        let count = data.len() as u32;
        if data.is_empty() {
            // wgpu rejects empty bindings; nothing is drawn from this one.
            data.push(Edge::zeroed());
        }
        let buffer = ctx.storage_buffer("penumbra edges", bytemuck::cast_slice(&data));
        Self { buffer, count }
    }
}

/// Steps 2 and 3 of silhouette extrusion: ribbons into `edge`, back faces into `lower`.
#[allow(clippy::too_many_arguments)]
fn encode_silhouette(
    ctx: &GpuContext,
    enc: &mut wgpu::CommandEncoder,
    scene: &GpuScene,
    uniform: &wgpu::Buffer,
    geom: &wgpu::Buffer,
    edge: &wgpu::Texture,
    lower: &wgpu::Texture,
    resolution: u32,
) -> Result<()> {
    let pipes = ctx.cached(SilhouettePipelines::new);
    let tris = scene.casters();
    let edges = scene.derived(ctx, |c, g| Ok(GpuEdges::new(c, g)))?;
    let (eb, edge_count) = (&edges.buffer, edges.count);
    let depth = texture_2d(
        ctx,
        "penumbra ribbon depth",
        resolution,
        (1, 1),
        DEPTH_FORMAT,
        wgpu::TextureUsages::RENDER_ATTACHMENT,
    );
    let dummy = texture_2d(
        ctx,
        "penumbra no edges",
        1,
        (1, 1),
        EDGE_FORMAT,
        wgpu::TextureUsages::TEXTURE_BINDING,
    );
    let (edge_view, lower_view, depth_view) = (
        edge.create_view(&Default::default()),
        lower.create_view(&Default::default()),
        depth.create_view(&Default::default()),
    );
    let bind = |tex: &wgpu::TextureView| {
        bind_group(
            ctx,
            "penumbra silhouette",
            &pipes.layout,
            &[
                uniform.as_entire_binding(),
                eb.as_entire_binding(),
                wgpu::BindingResource::TextureView(tex),
                geom.as_entire_binding(),
            ],
        )
    };
    let ribbon_bind = bind(&dummy.create_view(&Default::default()));
    let no_edge = wgpu::Color {
        r: NONE_DEPTH as f64,
        g: crate::storage::MAX_P as f64,
        b: 0.0,
        a: 0.0,
    };
    {
        let mut rp = render_pass(
            ctx,
            enc,
            "penumbra ribbons",
            &edge_view,
            no_edge,
            &depth_view,
            1.0,
        );
        rp.set_pipeline(&pipes.ribbons);
        rp.set_bind_group(0, &ribbon_bind, &[]);
        rp.draw(0..edge_count * 12, 0..1);
    }
    let lower_bind = bind(&edge_view);
    let none = wgpu::Color {
        r: NONE_DEPTH as f64,
        ..wgpu::Color::BLACK
    };
    let mut rp = render_pass(
        ctx,
        enc,
        "penumbra lower limit",
        &lower_view,
        none,
        &depth_view,
        0.0,
    );
    if tris.vertex_count > 0 {
        rp.set_pipeline(&pipes.lower);
        rp.set_bind_group(0, &lower_bind, &[]);
        rp.set_vertex_buffer(0, tris.vertices.slice(..));
        rp.draw(0..tris.vertex_count, 0..1);
    }
    drop(rp);
    ctx.recycle_texture(depth);
    ctx.recycle_texture(dummy);
    Ok(())
}

/// Records the map into `enc` (inputs already checked).
pub(crate) fn generate(
    ctx: &GpuContext,
    enc: &mut wgpu::CommandEncoder,
    t: &PenumbraLimit,
    scene: &GpuScene,
    input: &Generation,
) -> Result<GpuPenumbraMaps> {
    let light = input.light;
    let resolution = input.resolution;
    let texels = resolution as u64 * resolution as u64;
    let raster = ctx.cached(GpuRasterizer::new);
    let di = ctx.cached(DepthImagePipelines::new);
    let comb = ctx.cached(CombinePipelines::new);
    let view = SampleView::center(light, &input.coverage());
    let params = view.params(resolution);
    let warp = Warp::new(&params, light);
    let tris = scene.casters();
    let depth = GpuRasterizer::depth_array(ctx, resolution, 1)?;
    let gen_params = GenParams {
        map: params,
        warp,
        resolution,
        layer_gap: t.layer_gap,
        transition_gap: t.transition_gap,
        _pad: 0.0,
    };
    let uniform = ctx.uniform_buffer("penumbra params", bytemuck::bytes_of(&gen_params));
    let seeds_bytes = if t.generator == Generator::DepthImage {
        texels * 4
    } else {
        4
    };
    let geom = storage_buffer(ctx, "penumbra geometry", texels * 4);
    let seeds = [0, 1, 2, 3].map(|_| storage_buffer(ctx, "penumbra seeds", seeds_bytes));
    let edge = texture_2d(
        ctx,
        "penumbra edge",
        resolution,
        (1, 1),
        EDGE_FORMAT,
        layer_usage(),
    );
    let lower = texture_2d(
        ctx,
        "penumbra lower",
        resolution,
        (1, 1),
        LOWER_FORMAT,
        layer_usage(),
    );
    let map = texture_2d(
        ctx,
        "penumbra limit map",
        resolution,
        (1, 1),
        t.storage.texture_format(),
        wgpu::TextureUsages::STORAGE_BINDING
            | wgpu::TextureUsages::TEXTURE_BINDING
            | wgpu::TextureUsages::COPY_SRC,
    );
    let (edge_view, lower_view) = (
        edge.create_view(&Default::default()),
        lower.create_view(&Default::default()),
    );
    let depth_view = depth_array_view(&depth);
    let di_bind = |a: &wgpu::Buffer, b: &wgpu::Buffer| {
        bind_group(
            ctx,
            "penumbra depth image",
            &di.layout,
            &[
                uniform.as_entire_binding(),
                wgpu::BindingResource::TextureView(&depth_view),
                geom.as_entire_binding(),
                a.as_entire_binding(),
                b.as_entire_binding(),
                wgpu::BindingResource::TextureView(&edge_view),
                wgpu::BindingResource::TextureView(&lower_view),
            ],
        )
    };
    raster.encode_depth_pass(ctx, enc, tris, &view.view, &depth, 0, DepthPass::NEAREST);
    dispatch(
        ctx,
        enc,
        &di.geometry,
        &di_bind(&seeds[0], &seeds[1]),
        resolution,
    );
    match t.generator {
        Generator::Silhouette => {
            encode_silhouette(ctx, enc, scene, &uniform, &geom, &edge, &lower, resolution)?;
        }
        Generator::DepthImage => {
            dispatch(
                ctx,
                enc,
                &di.seeds,
                &di_bind(&seeds[0], &seeds[1]),
                resolution,
            );
            let ft = ctx.cached(GpuFeatureTransform::new);
            // Near-side ties to the nearer depth, as on the CPU.
            ft.encode(ctx, enc, [&seeds[0], &seeds[2]], Some(&geom), resolution);
            ft.encode(ctx, enc, [&seeds[1], &seeds[3]], None, resolution);
            dispatch(
                ctx,
                enc,
                &di.limits,
                &di_bind(&seeds[0], &seeds[1]),
                resolution,
            );
        }
    }
    let k = CombinePipelines::index(t.storage);
    let map_view = map.create_view(&Default::default());
    let cb = bind_group(
        ctx,
        "penumbra combine",
        &comb.layouts[k],
        &[
            uniform.as_entire_binding(),
            geom.as_entire_binding(),
            wgpu::BindingResource::TextureView(&edge_view),
            wgpu::BindingResource::TextureView(&lower_view),
            wgpu::BindingResource::TextureView(&map_view),
        ],
    );
    dispatch(ctx, enc, &comb.pipelines[k], &cb, resolution);
    // Scratch back to the pool: the passes recorded above still run first.
    for texture in [depth, edge, lower] {
        ctx.recycle_texture(texture);
    }
    for buffer in [geom].into_iter().chain(seeds) {
        ctx.recycle_buffer(buffer);
    }
    Ok(GpuPenumbraMaps {
        params,
        warp,
        map,
        storage: t.storage,
        table: IlluminationTable::new(t.profile.for_light(light), t.table_size),
    })
}

/// The bind group of `maps` read with `t`'s biases.
pub(crate) fn bind_maps(
    ctx: &GpuContext,
    layout: &wgpu::BindGroupLayout,
    t: &PenumbraLimit,
    maps: &GpuPenumbraMaps,
) -> wgpu::BindGroup {
    let prm = EvalParams::new(
        maps.params,
        t.bias,
        maps.warp,
        maps.storage,
        maps.table.values.len() as u32,
    );
    let ub = ctx.uniform_buffer("penumbra eval", bytemuck::bytes_of(&prm));
    let tb = ctx.storage_buffer(
        "illumination table",
        bytemuck::cast_slice(&maps.table.values),
    );
    let map_view = maps.map.create_view(&Default::default());
    bind_group(
        ctx,
        "penumbra evaluate",
        layout,
        &[
            ub.as_entire_binding(),
            wgpu::BindingResource::TextureView(&map_view),
            tb.as_entire_binding(),
        ],
    )
}
