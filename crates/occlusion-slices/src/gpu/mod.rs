//! The GPU path. Generation records everything in one command buffer and reads nothing back:
//!
//! 1. the slicing render pass (`slicing.wgsl`): casters from the COP into `ceil(n / 4)` RGBA8
//!    layers, four slices per texel, `Max`-blended;
//! 2. the summed-area table of integer counts (`sat_rows.wgsl`, `sat_cols.wgsl`), with
//!    [`crate::Combination::Chain`] also of the unions of neighbouring slices, in as many layers
//!    again after the slices';
//! 3. for N-Buffers and mipmaps, every level from the table (`levels.wgsl`), RGBA8.
//!
//! Evaluation is `visibility()` in `visibility.wgsl`.

pub(crate) mod pipelines;

use crate::filters::level_count;
use crate::filters::mipmap::mip_size;
use crate::frame::Frame;
use crate::params::{OcclusionSlices, Prefilter};
use bytemuck::{Pod, Zeroable};
use pipelines::{LEVEL_FORMAT, OCCUPANCY_FORMAT, PrefilterPipelines, SAT_FORMAT, SlicingPipelines};
use soft_shadow_core::gpu::Kernel;
use soft_shadow_core::gpu::compute::{self, bind_group};
use soft_shadow_core::gpu::raster::read_texture;
use soft_shadow_core::gpu::resources::texture_2d;
use soft_shadow_core::gpu::timer::PassSlot;
use soft_shadow_core::gpu::{GpuScene, GpuTriangles};
use soft_shadow_core::{Generation, GpuContext, Result, ShadowError};

/// The occlusion textures of one light, kept on the GPU.
pub struct GpuSliceMaps {
    /// The slicing frame.
    pub(crate) frame: Frame,
    /// The filter the maps were built for.
    pub(crate) filter: Prefilter,
    /// Groups of four slices (RGBA texels).
    pub(crate) groups: u32,
    /// Whether the table and levels hold the unions of neighbouring slices
    /// ([`crate::Combination::Chain`]) in `groups` layers after the slices'.
    pub(crate) chained: bool,
    /// Mipmap or N-Buffer levels.
    pub(crate) levels: u32,
    /// The slices: `groups` RGBA8 layers, each channel a slice's top codes
    /// ([`Frame::top_code`] / 255; 0 where empty).
    pub(crate) occupancy: wgpu::Texture,
    /// The summed-area table (`resolution + 1` a side, [`GpuSliceMaps::table_groups`] layers
    /// of RGBA32Uint); kept for [`Prefilter::Sat`], a 1x1 placeholder otherwise.
    pub(crate) sat: wgpu::Texture,
    /// N-Buffer levels (`levels * table_groups` layers) or the mip pyramid (`table_groups`
    /// layers, `levels` mips); a 1x1 placeholder for [`Prefilter::Sat`].
    pub(crate) filtered: wgpu::Texture,
}

/// Layers of the table and of each level: the slices' groups, twice over with the unions.
fn table_groups(groups: u32, chained: bool) -> u32 {
    groups * (1 + chained as u32)
}

impl GpuSliceMaps {
    /// Layers of the table and of each level.
    fn table_groups(&self) -> u32 {
        table_groups(self.groups, self.chained)
    }

    /// Reads the binary slices back (tests): `slices` maps of `resolution²` flags.
    pub fn read_slices(&self, ctx: &GpuContext) -> Result<Vec<Vec<bool>>> {
        let mut out = vec![Vec::new(); self.frame.slices as usize];
        for g in 0..self.groups {
            let texels: Vec<[u8; 4]> =
                read_texture(ctx, &self.occupancy, g, wgpu::TextureAspect::All, 4)?;
            for c in 0..4 {
                let k = (g * 4 + c) as usize;
                if k < out.len() {
                    out[k] = texels.iter().map(|t| t[c as usize] != 0).collect();
                }
            }
        }
        Ok(out)
    }

    /// Reads the N-Buffer levels back (tests): per slice, per level, `resolution²` unorm8 texels; empty
    /// for the other filters.
    pub fn read_nbuffer(&self, ctx: &GpuContext) -> Result<Vec<Vec<Vec<u8>>>> {
        if self.filter != Prefilter::NBuffer {
            return Ok(Vec::new());
        }
        let slices = self.frame.slices as usize;
        let mut out = vec![Vec::new(); slices];
        for l in 0..self.levels {
            for g in 0..self.groups {
                let layer = l * self.table_groups() + g;
                let texels: Vec<[u8; 4]> =
                    read_texture(ctx, &self.filtered, layer, wgpu::TextureAspect::All, 4)?;
                for c in 0..4 {
                    let k = (g * 4 + c) as usize;
                    if k < slices {
                        out[k].push(texels.iter().map(|t| t[c as usize]).collect());
                    }
                }
            }
        }
        Ok(out)
    }
}

/// Per-level parameters, laid out as `Level` in `levels.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
pub(crate) struct LevelParams {
    level: u32,
    groups: u32,
    size: u32,
    _pad: u32,
}

/// Evaluation parameters (binding 1 of the maps' bind group), laid out as `EvalParams` in
/// `visibility.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub(crate) struct EvalParams {
    /// [`Prefilter::index`].
    pub filter: u32,
    /// [`crate::params::Combination::index`].
    pub combination: u32,
    /// Mipmap or N-Buffer levels.
    pub levels: u32,
    /// Where the unions of neighbouring slices begin, as a slice index (`4 * groups`).
    pub unions: u32,
    /// Receiver offset along its normal, in texels.
    pub normal_offset: f32,
    /// Layers of each level ([`GpuSliceMaps::table_groups`]).
    pub groups: u32,
    /// Padding to 16 bytes.
    pub _pad: [u32; 2],
}

fn array_view(t: &wgpu::Texture, mip: Option<u32>) -> wgpu::TextureView {
    t.create_view(&wgpu::TextureViewDescriptor {
        dimension: Some(wgpu::TextureViewDimension::D2Array),
        base_mip_level: mip.unwrap_or(0),
        mip_level_count: mip.map(|_| 1),
        ..Default::default()
    })
}

/// Tables and levels: written by the kernels, read by evaluation, copied out by
/// [`GpuSliceMaps::read_nbuffer`].
fn storage_usage() -> wgpu::TextureUsages {
    wgpu::TextureUsages::STORAGE_BINDING
        | wgpu::TextureUsages::TEXTURE_BINDING
        | wgpu::TextureUsages::COPY_SRC
}

/// Step 1: the slicing render pass into the `groups` layers of `occupancy`.
fn encode_slicing(
    ctx: &GpuContext,
    enc: &mut wgpu::CommandEncoder,
    tris: &GpuTriangles,
    uniform: &wgpu::Buffer,
    occupancy: &wgpu::Texture,
    groups: u32,
) {
    let pipes = ctx.cached(SlicingPipelines::new);
    let views: Vec<wgpu::TextureView> = (0..groups)
        .map(|g| {
            occupancy.create_view(&wgpu::TextureViewDescriptor {
                dimension: Some(wgpu::TextureViewDimension::D2),
                base_array_layer: g,
                array_layer_count: Some(1),
                ..Default::default()
            })
        })
        .collect();
    // Four slots, as the pipeline's targets: the unused ones are `None` on both sides.
    let mut attachments: Vec<Option<wgpu::RenderPassColorAttachment>> = views
        .iter()
        .map(|view| {
            Some(wgpu::RenderPassColorAttachment {
                view,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
                    store: wgpu::StoreOp::Store,
                },
            })
        })
        .collect();
    attachments.resize(4, None);
    let bind = bind_group(
        ctx,
        "slicing",
        &pipes.layout,
        &[uniform.as_entire_binding()],
    );
    let slot = ctx.pass_slot();
    let mut rp = enc.begin_render_pass(&wgpu::RenderPassDescriptor {
        label: Some("slicing"),
        color_attachments: &attachments,
        depth_stencil_attachment: None,
        timestamp_writes: slot.as_ref().map(PassSlot::render_writes),
        occlusion_query_set: None,
        multiview_mask: None,
    });
    if tris.vertex_count > 0 {
        rp.set_pipeline(&pipes.pipelines[groups as usize - 1]);
        rp.set_bind_group(0, &bind, &[]);
        rp.set_vertex_buffer(0, tris.vertices.slice(..));
        rp.draw(0..tris.vertex_count, 0..1);
    }
}

/// Step 3: every level of `filtered` from the table.
#[allow(clippy::too_many_arguments)]
fn encode_levels(
    ctx: &GpuContext,
    enc: &mut wgpu::CommandEncoder,
    pre: &PrefilterPipelines,
    uniform: &wgpu::Buffer,
    sat_view: &wgpu::TextureView,
    filtered: &wgpu::Texture,
    filter: Prefilter,
    resolution: u32,
    groups: u32,
) {
    let whole = array_view(filtered, None);
    for l in 0..level_count(resolution) {
        let (kernel, size, out) = match filter {
            Prefilter::NBuffer => (&pre.nbuffer_level, resolution, None),
            _ => (
                &pre.mip_level,
                mip_size(resolution, l),
                Some(array_view(filtered, Some(l))),
            ),
        };
        let lp = LevelParams {
            level: l,
            groups,
            size,
            _pad: 0,
        };
        let lb = ctx.uniform_buffer("level", bytemuck::bytes_of(&lp));
        let bind = bind_group(
            ctx,
            "level",
            &kernel.layout,
            &[
                uniform.as_entire_binding(),
                wgpu::BindingResource::TextureView(sat_view),
                lb.as_entire_binding(),
                wgpu::BindingResource::TextureView(out.as_ref().unwrap_or(&whole)),
            ],
        );
        let g = size.div_ceil(8);
        compute::dispatch(ctx, enc, "level", &kernel.pipeline, &bind, (g, g, groups));
    }
}

/// Records the occlusion textures into `enc` (inputs already checked).
pub(crate) fn generate(
    ctx: &GpuContext,
    enc: &mut wgpu::CommandEncoder,
    t: &OcclusionSlices,
    scene: &GpuScene,
    input: &Generation,
) -> Result<GpuSliceMaps> {
    let (geometry, light, resolution) = (input.geometry, input.light, input.resolution);
    let limits = ctx.device.limits();
    let levels = level_count(resolution);
    let groups = t.slices.div_ceil(4);
    let chained = t.combination.chained();
    let tables = table_groups(groups, chained);
    if levels * tables > limits.max_texture_array_layers {
        return Err(ShadowError::Gpu(format!(
            "{} N-Buffer layers exceed the device's {}",
            levels * tables,
            limits.max_texture_array_layers
        )));
    }
    let frame = Frame::fit(light, geometry, t, resolution, input.region);
    let uniform = ctx.uniform_buffer("slicing frame", bytemuck::bytes_of(&frame));
    let pre = ctx.cached(PrefilterPipelines::new);
    let occupancy = texture_2d(
        ctx,
        "occlusion textures",
        resolution,
        (groups, 1),
        OCCUPANCY_FORMAT,
        wgpu::TextureUsages::RENDER_ATTACHMENT
            | wgpu::TextureUsages::TEXTURE_BINDING
            | wgpu::TextureUsages::COPY_SRC,
    );
    let table = |label| {
        texture_2d(
            ctx,
            label,
            resolution + 1,
            (tables, 1),
            SAT_FORMAT,
            storage_usage(),
        )
    };
    // The row-prefix table is a pure temporary, from the pool and back: allocating fresh GPU
    // memory cost more than the prefiltering itself at 2048² (measured on an H100).
    let rows = table("sat rows");
    let sat = table("summed-area table");
    let filtered = match t.filter {
        Prefilter::Sat => texture_2d(ctx, "no levels", 1, (1, 1), LEVEL_FORMAT, storage_usage()),
        Prefilter::NBuffer => texture_2d(
            ctx,
            "n-buffers",
            resolution,
            (levels * tables, 1),
            LEVEL_FORMAT,
            storage_usage(),
        ),
        // The next power of two: its mip chain has room for every level (level l holds
        // ceil(resolution / 2^l) texels a side, more than a `resolution`-wide texture's level l, and
        // `levels` levels, one more than its chain where `resolution` is no power of two).
        Prefilter::Mipmap => texture_2d(
            ctx,
            "mipmaps",
            resolution.next_power_of_two(),
            (tables, levels),
            LEVEL_FORMAT,
            storage_usage(),
        ),
    };
    encode_slicing(ctx, enc, scene.casters(), &uniform, &occupancy, groups);
    let (occ_view, rows_view, sat_view) = (
        array_view(&occupancy, None),
        array_view(&rows, None),
        array_view(&sat, None),
    );
    // One invocation per table row, then per table column.
    let scan_groups = (resolution + 1).div_ceil(64);
    let bind = |k: &Kernel, src: &wgpu::TextureView, dst: &wgpu::TextureView| {
        bind_group(
            ctx,
            "sat scan",
            &k.layout,
            &[
                uniform.as_entire_binding(),
                wgpu::BindingResource::TextureView(src),
                wgpu::BindingResource::TextureView(dst),
            ],
        )
    };
    let b = bind(&pre.sat_rows, &occ_view, &rows_view);
    compute::dispatch(
        ctx,
        enc,
        "sat rows",
        &pre.sat_rows.pipeline,
        &b,
        (scan_groups, tables, 1),
    );
    let b = bind(&pre.sat_cols, &rows_view, &sat_view);
    compute::dispatch(
        ctx,
        enc,
        "sat cols",
        &pre.sat_cols.pipeline,
        &b,
        (scan_groups, tables, 1),
    );
    if t.filter != Prefilter::Sat {
        encode_levels(
            ctx, enc, &pre, &uniform, &sat_view, &filtered, t.filter, resolution, tables,
        );
    }
    ctx.recycle_texture(rows);
    let sat = if t.filter == Prefilter::Sat {
        sat
    } else {
        ctx.recycle_texture(sat);
        texture_2d(ctx, "no table", 1, (1, 1), SAT_FORMAT, storage_usage())
    };
    Ok(GpuSliceMaps {
        frame,
        filter: t.filter,
        groups,
        chained,
        levels,
        occupancy,
        sat,
        filtered,
    })
}

/// The bind group of `maps` read with `t`'s filter and combination; maps built with another
/// filter or slice count are [`ShadowError::MapsMismatch`].
pub(crate) fn bind_maps(
    ctx: &GpuContext,
    layout: &wgpu::BindGroupLayout,
    t: &OcclusionSlices,
    maps: &GpuSliceMaps,
) -> Result<wgpu::BindGroup> {
    crate::cpu::check_maps(t, maps.filter, maps.frame.slices, maps.chained)?;
    let prm = EvalParams {
        filter: t.filter.index(),
        combination: t.combination.index(),
        levels: maps.levels,
        unions: 4 * maps.groups,
        normal_offset: t.normal_offset,
        groups: maps.table_groups(),
        _pad: [0; 2],
    };
    let fb = ctx.uniform_buffer("slicing frame", bytemuck::bytes_of(&maps.frame));
    let eb = ctx.uniform_buffer("occlusion eval", bytemuck::bytes_of(&prm));
    let (sat_view, levels_view, tops_view) = (
        array_view(&maps.sat, None),
        array_view(&maps.filtered, None),
        array_view(&maps.occupancy, None),
    );
    Ok(bind_group(
        ctx,
        "occlusion evaluate",
        layout,
        &[
            fb.as_entire_binding(),
            eb.as_entire_binding(),
            wgpu::BindingResource::TextureView(&sat_view),
            wgpu::BindingResource::TextureView(&levels_view),
            wgpu::BindingResource::TextureView(&tops_view),
        ],
    ))
}
