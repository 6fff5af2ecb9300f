//! GPU render passes: light-space depth maps and the camera G-buffer.
//!
//! Same conventions as [`crate::raster`]: reversed-Z `Depth32Float` cleared to 0 with a `Greater`
//! test, no culling, row 0 at the top. Tests check both against the CPU rasterizer.

use super::GpuContext;
use super::shader::RASTER;
use super::timer::PassSlot;
use crate::error::{Result, ShadowError};
use crate::map2d::Map2D;
use crate::raster::{DepthPass, DepthTest, Faces, GBufferTexel, facing_normal};
use crate::view::View;
use glam::{Mat4, Vec3};

/// Depth format of every light-space map.
pub const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;

/// World-space triangles uploaded as a non-indexed vertex buffer of positions.
pub struct GpuTriangles {
    /// `vec3<f32>` per vertex, three per triangle.
    pub vertices: wgpu::Buffer,
    /// Number of vertices.
    pub vertex_count: u32,
}

impl GpuTriangles {
    /// Uploads triangles; more than the device's largest buffer is [`ShadowError::Gpu`].
    pub fn new(ctx: &GpuContext, tris: &[[Vec3; 3]]) -> Result<Self> {
        let bytes = tris.len() as u64 * 36;
        let max = ctx.device.limits().max_buffer_size;
        if bytes > max {
            return Err(ShadowError::Gpu(format!(
                "{} triangles need a {bytes}-byte vertex buffer; the device allows {max}",
                tris.len()
            )));
        }
        let flat: Vec<[f32; 3]> = tris.iter().flat_map(|t| t.map(|p| p.to_array())).collect();
        let vertices = vertex_buffer(ctx, "triangles", bytemuck::cast_slice(&flat));
        Ok(Self {
            vertices,
            vertex_count: flat.len() as u32,
        })
    }
}

/// The G-buffer read back from the GPU.
pub type GpuGBuffer = Map2D<GBufferTexel>;

/// Pipelines for depth maps and G-buffers; create once per [`GpuContext`] and reuse.
pub struct GpuRasterizer {
    /// Depth-only pipelines indexed by [`pass_index`].
    depth: [wgpu::RenderPipeline; 4],
    gbuffer: wgpu::RenderPipeline,
    layout: wgpu::BindGroupLayout,
}

/// A vertex buffer holding `bytes` (one zero vertex when empty: wgpu rejects empty buffers).
fn vertex_buffer(ctx: &GpuContext, label: &str, bytes: &[u8]) -> wgpu::Buffer {
    let bytes = if bytes.is_empty() {
        &[0u8; 24][..]
    } else {
        bytes
    };
    ctx.buffer_with(label, bytes, wgpu::BufferUsages::VERTEX)
}

fn pass_index(pass: DepthPass) -> usize {
    (pass.test == DepthTest::Farthest) as usize * 2 + (pass.faces == Faces::Back) as usize
}

/// A depth attachment cleared to `pass`'s clear depth (0, the far plane of reversed Z, for the
/// nearest-surface pass).
fn cleared_depth(
    view: &wgpu::TextureView,
    pass: DepthPass,
) -> Option<wgpu::RenderPassDepthStencilAttachment<'_>> {
    Some(wgpu::RenderPassDepthStencilAttachment {
        view,
        depth_ops: Some(wgpu::Operations {
            load: wgpu::LoadOp::Clear(pass.clear_depth()),
            store: wgpu::StoreOp::Store,
        }),
        stencil_ops: None,
    })
}

fn padded_row(bytes: u32) -> u32 {
    bytes.div_ceil(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT) * wgpu::COPY_BYTES_PER_ROW_ALIGNMENT
}

impl GpuRasterizer {
    /// Builds the pipelines.
    pub fn new(ctx: &GpuContext) -> Self {
        let device = &ctx.device;
        let program = ctx.program(&RASTER);
        let (module, layout, pl) = (
            &program.module,
            program.layouts[0].clone(),
            &program.pipeline_layout,
        );
        let depth_state = wgpu::DepthStencilState {
            format: DEPTH_FORMAT,
            depth_write_enabled: Some(true),
            depth_compare: Some(wgpu::CompareFunction::Greater),
            stencil: Default::default(),
            bias: Default::default(),
        };
        let primitive = wgpu::PrimitiveState {
            cull_mode: None,
            ..Default::default()
        };
        let depth_pipeline = |pass: DepthPass| {
            device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some("depth"),
                layout: Some(pl),
                vertex: wgpu::VertexState {
                    module,
                    entry_point: Some("vs_depth"),
                    compilation_options: Default::default(),
                    buffers: &[Some(wgpu::VertexBufferLayout {
                        array_stride: 12,
                        step_mode: wgpu::VertexStepMode::Vertex,
                        attributes: &wgpu::vertex_attr_array![0 => Float32x3],
                    })],
                },
                primitive: wgpu::PrimitiveState {
                    cull_mode: (pass.faces == Faces::Back).then_some(wgpu::Face::Front),
                    ..primitive
                },
                depth_stencil: Some(wgpu::DepthStencilState {
                    depth_compare: Some(match pass.test {
                        DepthTest::Nearest => wgpu::CompareFunction::Greater,
                        DepthTest::Farthest => wgpu::CompareFunction::Less,
                    }),
                    ..depth_state.clone()
                }),
                multisample: Default::default(),
                fragment: None,
                multiview_mask: None,
                cache: None,
            })
        };
        let depth = [
            DepthPass::NEAREST,
            DepthPass::NEAREST_BACK,
            DepthPass::FARTHEST,
            DepthPass::FARTHEST_BACK,
        ]
        .map(depth_pipeline);
        let target = Some(wgpu::ColorTargetState {
            format: wgpu::TextureFormat::Rgba32Float,
            blend: None,
            write_mask: wgpu::ColorWrites::ALL,
        });
        let gbuffer = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("gbuffer"),
            layout: Some(pl),
            vertex: wgpu::VertexState {
                module,
                entry_point: Some("vs_gbuffer"),
                compilation_options: Default::default(),
                buffers: &[Some(wgpu::VertexBufferLayout {
                    array_stride: 24,
                    step_mode: wgpu::VertexStepMode::Vertex,
                    attributes: &wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3],
                })],
            },
            primitive,
            depth_stencil: Some(depth_state),
            multisample: Default::default(),
            fragment: Some(wgpu::FragmentState {
                module,
                entry_point: Some("fs_gbuffer"),
                compilation_options: Default::default(),
                targets: &[target.clone(), target],
            }),
            multiview_mask: None,
            cache: None,
        });
        Self {
            depth,
            gbuffer,
            layout,
        }
    }

    fn view_bind_group(&self, ctx: &GpuContext, view_proj: Mat4) -> wgpu::BindGroup {
        let buf = ctx.uniform_buffer("view", bytemuck::bytes_of(&view_proj.to_cols_array()));
        ctx.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("view"),
            layout: &self.layout,
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: buf.as_entire_binding(),
            }],
        })
    }

    /// A `resolution²` array of `layers` depth maps, usable as render target and texture.
    pub fn depth_array(ctx: &GpuContext, resolution: u32, layers: u32) -> Result<wgpu::Texture> {
        let max = ctx.max_texture_size();
        if resolution == 0 || resolution > max {
            return Err(ShadowError::InvalidResolution {
                requested: resolution,
                max,
            });
        }
        let max_layers = ctx.device.limits().max_texture_array_layers;
        if layers == 0 || layers > max_layers {
            return Err(ShadowError::Gpu(format!(
                "{layers} depth layers asked for; the device allows 1..={max_layers}"
            )));
        }
        Ok(ctx.texture(&wgpu::TextureDescriptor {
            label: Some("depth maps"),
            size: wgpu::Extent3d {
                width: resolution,
                height: resolution,
                depth_or_array_layers: layers,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: DEPTH_FORMAT,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT
                | wgpu::TextureUsages::TEXTURE_BINDING
                | wgpu::TextureUsages::COPY_SRC,
            view_formats: &[],
        }))
    }

    /// Records a nearest-surface depth pass of `tris` seen through `view` into layer `layer` of
    /// `target`.
    pub fn encode_depth(
        &self,
        ctx: &GpuContext,
        enc: &mut wgpu::CommandEncoder,
        tris: &GpuTriangles,
        view: &View,
        target: &wgpu::Texture,
        layer: u32,
    ) {
        self.encode_depth_pass(ctx, enc, tris, view, target, layer, DepthPass::NEAREST);
    }

    /// Records the depth pass `pass` of `tris` seen through `view` into layer `layer` of `target`.
    #[allow(clippy::too_many_arguments)]
    pub fn encode_depth_pass(
        &self,
        ctx: &GpuContext,
        enc: &mut wgpu::CommandEncoder,
        tris: &GpuTriangles,
        view: &View,
        target: &wgpu::Texture,
        layer: u32,
        pass: DepthPass,
    ) {
        let bind = self.view_bind_group(ctx, view.view_projection());
        let tv = target.create_view(&wgpu::TextureViewDescriptor {
            dimension: Some(wgpu::TextureViewDimension::D2),
            base_array_layer: layer,
            array_layer_count: Some(1),
            ..Default::default()
        });
        let slot = ctx.pass_slot();
        let mut rp = enc.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("depth"),
            color_attachments: &[],
            depth_stencil_attachment: cleared_depth(&tv, pass),
            timestamp_writes: slot.as_ref().map(PassSlot::render_writes),
            occlusion_query_set: None,
            multiview_mask: None,
        });
        if tris.vertex_count > 0 {
            rp.set_pipeline(&self.depth[pass_index(pass)]);
            rp.set_bind_group(0, &bind, &[]);
            rp.set_vertex_buffer(0, tris.vertices.slice(..));
            rp.draw(0..tris.vertex_count, 0..1);
        }
    }

    /// Reads one layer of a nearest-surface depth array back as a linear depth map (for tests
    /// and reports).
    pub fn read_depth(
        &self,
        ctx: &GpuContext,
        target: &wgpu::Texture,
        layer: u32,
        view: &View,
    ) -> Result<Map2D<f32>> {
        Self::read_depth_pass(ctx, target, layer, view, DepthPass::NEAREST)
    }

    /// Reads one layer of a depth array rendered by `pass` back as a linear depth map.
    pub fn read_depth_pass(
        ctx: &GpuContext,
        target: &wgpu::Texture,
        layer: u32,
        view: &View,
        pass: DepthPass,
    ) -> Result<Map2D<f32>> {
        let (w, h) = (target.width(), target.height());
        let mut lin: Vec<f32> =
            read_texture(ctx, target, layer, wgpu::TextureAspect::DepthOnly, 4)?;
        pass.linearize(view, &mut lin);
        Map2D::from_vec(w, h, lin).ok_or_else(|| ShadowError::Gpu("depth readback size".into()))
    }

    /// Renders one depth map and reads it back as linear depth.
    pub fn depth_map(
        &self,
        ctx: &GpuContext,
        tris: &GpuTriangles,
        view: &View,
        resolution: u32,
    ) -> Result<Map2D<f32>> {
        let tex = Self::depth_array(ctx, resolution, 1)?;
        let mut enc = ctx.device.create_command_encoder(&Default::default());
        self.encode_depth(ctx, &mut enc, tris, view, &tex, 0);
        ctx.queue.submit([enc.finish()]);
        self.read_depth(ctx, &tex, 0, view)
    }

    /// Renders the camera G-buffer of `tris` (normals flipped to face `eye`) and reads it back.
    pub fn gbuffer(
        &self,
        ctx: &GpuContext,
        tris: &[[Vec3; 3]],
        view: &View,
        eye: Vec3,
        width: u32,
        height: u32,
    ) -> Result<GpuGBuffer> {
        ctx.checked("g-buffer", || {
            self.gbuffer_unchecked(ctx, tris, view, eye, width, height)
        })
    }

    fn gbuffer_unchecked(
        &self,
        ctx: &GpuContext,
        tris: &[[Vec3; 3]],
        view: &View,
        eye: Vec3,
        width: u32,
        height: u32,
    ) -> Result<GpuGBuffer> {
        if tris.len() as u64 * 72 > ctx.device.limits().max_buffer_size {
            return Err(ShadowError::Gpu(format!(
                "{} triangles exceed the device's largest vertex buffer",
                tris.len()
            )));
        }
        let max = ctx.max_texture_size();
        if width == 0 || height == 0 || width.max(height) > max {
            return Err(ShadowError::InvalidResolution {
                requested: width.max(height),
                max,
            });
        }
        let verts: Vec<[f32; 6]> = tris
            .iter()
            .flat_map(|t| {
                let n = facing_normal(t, eye);
                t.map(|p| [p.x, p.y, p.z, n.x, n.y, n.z])
            })
            .collect();
        let vb = vertex_buffer(ctx, "gbuffer vertices", bytemuck::cast_slice(&verts));
        let size = wgpu::Extent3d {
            width,
            height,
            depth_or_array_layers: 1,
        };
        let color = |label| {
            ctx.device.create_texture(&wgpu::TextureDescriptor {
                label: Some(label),
                size,
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format: wgpu::TextureFormat::Rgba32Float,
                usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
                view_formats: &[],
            })
        };
        let (pos, nrm) = (color("gbuffer position"), color("gbuffer normal"));
        let depth = ctx.device.create_texture(&wgpu::TextureDescriptor {
            label: Some("gbuffer depth"),
            size,
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: DEPTH_FORMAT,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT,
            view_formats: &[],
        });
        let bind = self.view_bind_group(ctx, view.view_projection());
        let (pv, nv, dv) = (
            pos.create_view(&Default::default()),
            nrm.create_view(&Default::default()),
            depth.create_view(&Default::default()),
        );
        let mut enc = ctx.device.create_command_encoder(&Default::default());
        {
            let attach = |v| {
                Some(wgpu::RenderPassColorAttachment {
                    view: v,
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations {
                        load: wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
                        store: wgpu::StoreOp::Store,
                    },
                })
            };
            let slot = ctx.pass_slot();
            let mut pass = enc.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("gbuffer"),
                color_attachments: &[attach(&pv), attach(&nv)],
                depth_stencil_attachment: cleared_depth(&dv, DepthPass::NEAREST),
                timestamp_writes: slot.as_ref().map(PassSlot::render_writes),
                occlusion_query_set: None,
                multiview_mask: None,
            });
            if !verts.is_empty() {
                pass.set_pipeline(&self.gbuffer);
                pass.set_bind_group(0, &bind, &[]);
                pass.set_vertex_buffer(0, vb.slice(..));
                pass.draw(0..verts.len() as u32, 0..1);
            }
        }
        ctx.queue.submit([enc.finish()]);
        let p: Vec<[f32; 4]> = read_texture(ctx, &pos, 0, wgpu::TextureAspect::All, 16)?;
        let n: Vec<[f32; 4]> = read_texture(ctx, &nrm, 0, wgpu::TextureAspect::All, 16)?;
        let texels = p
            .iter()
            .zip(&n)
            .map(|(p, n)| GBufferTexel {
                position: Vec3::new(p[0], p[1], p[2]),
                normal: Vec3::new(n[0], n[1], n[2]),
                covered: p[3] > 0.5,
            })
            .collect();
        Map2D::from_vec(width, height, texels)
            .ok_or_else(|| ShadowError::Gpu("gbuffer readback size".into()))
    }
}

/// Copies one layer of a texture back, un-padding rows; `texel_bytes` per texel.
pub fn read_texture<T: bytemuck::Pod>(
    ctx: &GpuContext,
    tex: &wgpu::Texture,
    layer: u32,
    aspect: wgpu::TextureAspect,
    texel_bytes: u32,
) -> Result<Vec<T>> {
    let (w, h) = (tex.width(), tex.height());
    let row = padded_row(w * texel_bytes);
    let size = row as u64 * h as u64;
    let staging = ctx.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("texture readback"),
        size,
        usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    let mut enc = ctx.device.create_command_encoder(&Default::default());
    enc.copy_texture_to_buffer(
        wgpu::TexelCopyTextureInfo {
            texture: tex,
            mip_level: 0,
            origin: wgpu::Origin3d {
                x: 0,
                y: 0,
                z: layer,
            },
            aspect,
        },
        wgpu::TexelCopyBufferInfo {
            buffer: &staging,
            layout: wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(row),
                rows_per_image: Some(h),
            },
        },
        wgpu::Extent3d {
            width: w,
            height: h,
            depth_or_array_layers: 1,
        },
    );
    ctx.queue.submit([enc.finish()]);
    let bytes = ctx.map_read(&staging, size)?;
    let mut out = Vec::with_capacity((w * h) as usize);
    for y in 0..h as usize {
        let start = y * row as usize;
        let line = &bytes[start..start + (w * texel_bytes) as usize];
        out.extend_from_slice(bytemuck::pod_collect_to_vec::<u8, T>(line).as_slice());
    }
    Ok(out)
}
