//! The proof of drop-in use: a small wgpu renderer, with its own device, its own G-buffer and
//! shading passes, that takes one soft-shadow technique and never reads anything back to draw a
//! frame.
//!
//! Per frame it records into one encoder: its G-buffer pass, the technique's generation
//! ([`ShadowTechnique::record_gpu`] from a [`GpuScene`] uploaded once), the technique's
//! visibility over the G-buffer ([`ShadowTechnique::record_visibility`]) and its own Lambert
//! shading of one rectangular area light times `V`. [`shade::ShadeUniform::radiance`] is the same shading
//! in Rust, for the test that compares a frame with the CPU path.

pub mod shade;

use glam::{Mat4, Vec3};
use soft_shadow_core::gpu::shader::{
    Group, Library, Program, ShaderModule, float_texture, storage_texture, uniform,
};
use soft_shadow_core::gpu::visibility::ReceiverTextures;
use soft_shadow_core::gpu::{GpuContext, GpuScene};
use soft_shadow_core::{Camera, Light, Result, SceneGeometry, ShadowError, ShadowTechnique};
use wgpu::util::DeviceExt;

/// Format of the renderer's position and normal targets.
pub const GBUFFER_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Float;

/// What a frame looks like: image size, the technique's map side, the camera.
#[derive(Clone, Copy, Debug)]
pub struct FrameSettings {
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// Side of the technique's light-space maps.
    pub resolution: u32,
    /// The camera.
    pub camera: Camera,
}

/// The renderer: its device (wrapped in a [`GpuContext`]), its passes, its targets, and one
/// technique `T`.
pub struct Renderer<T: ShadowTechnique> {
    /// The renderer's device and queue, as the technique crates take them.
    pub gpu: GpuContext,
    technique: T,
    scene: GpuScene,
    settings: FrameSettings,
    vertices: wgpu::Buffer,
    vertex_count: u32,
    camera_bind: wgpu::BindGroup,
    gbuffer: wgpu::RenderPipeline,
    shade_pipeline: wgpu::ComputePipeline,
    shade_uniform: wgpu::Buffer,
    shade_bind: wgpu::BindGroup,
    targets: Targets,
}

struct Targets {
    position: wgpu::Texture,
    normal: wgpu::Texture,
    depth: wgpu::Texture,
    visibility: wgpu::Texture,
    color: wgpu::Texture,
}

fn target(
    device: &wgpu::Device,
    label: &str,
    (w, h): (u32, u32),
    format: wgpu::TextureFormat,
    usage: wgpu::TextureUsages,
) -> wgpu::Texture {
    device.create_texture(&wgpu::TextureDescriptor {
        label: Some(label),
        size: wgpu::Extent3d {
            width: w,
            height: h,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage,
        view_formats: &[],
    })
}

fn view(t: &wgpu::Texture) -> wgpu::TextureView {
    t.create_view(&Default::default())
}

/// Creates a device of its own, as an application would: the adapter wgpu picks by default
/// (`WGPU_BACKEND` restricts the backends), with WebGPU's default limits.
pub fn own_device() -> Result<(wgpu::Device, wgpu::Queue)> {
    pollster::block_on(async {
        let instance =
            wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle_from_env());
        let adapter = instance
            .request_adapter(&wgpu::RequestAdapterOptions::default())
            .await
            .map_err(|e| ShadowError::NoAdapter(e.to_string()))?;
        adapter
            .request_device(&wgpu::DeviceDescriptor {
                label: Some("example renderer"),
                ..Default::default()
            })
            .await
            .map_err(|e| ShadowError::Gpu(format!("request_device: {e}")))
    })
}

/// The renderer's own WGSL, composed by naga_oil like the library's.
pub static SHADERS: Library = Library {
    name: "example-renderer",
    modules: &[
        ShaderModule {
            path: "example_renderer::gbuffer",
            source: include_str!("gbuffer.wgsl"),
        },
        ShaderModule {
            path: "example_renderer::shade",
            source: include_str!("shade.wgsl"),
        },
    ],
    depends: &[],
    programs: &[&GBUFFER, &SHADE],
};

/// `gbuffer.wgsl`: the camera (view-projection and eye), read by both stages.
static GBUFFER: Program = Program {
    library: &SHADERS,
    module: "example_renderer::gbuffer",
    defs: &[],
    groups: &[Group {
        stages: wgpu::ShaderStages::VERTEX_FRAGMENT,
        bindings: &[uniform::<[f32; 20]>()],
    }],
};

/// `shade.wgsl`: the light, the G-buffer and `V`, the colour written.
static SHADE: Program = Program {
    library: &SHADERS,
    module: "example_renderer::shade",
    defs: &[],
    groups: &[Group::compute(&[
        uniform::<shade::ShadeUniform>(),
        float_texture(wgpu::TextureViewDimension::D2),
        float_texture(wgpu::TextureViewDimension::D2),
        float_texture(wgpu::TextureViewDimension::D2),
        storage_texture(
            wgpu::TextureFormat::Rgba8Unorm,
            wgpu::TextureViewDimension::D2,
        ),
    ])],
};

impl<T: ShadowTechnique> Renderer<T> {
    /// Builds the passes and targets and uploads `geometry` once (its surfaces for the
    /// renderer's own G-buffer, its casters for the technique).
    pub fn new(
        device: wgpu::Device,
        queue: wgpu::Queue,
        technique: T,
        geometry: &SceneGeometry,
        settings: FrameSettings,
    ) -> Result<Self> {
        let gpu = GpuContext::from_device(device, queue)?;
        let scene = GpuScene::new(&gpu, geometry)?;
        let d = &gpu.device;
        let size = (settings.width, settings.height);
        if size.0 == 0 || size.1 == 0 || size.0.max(size.1) > gpu.max_texture_size() {
            return Err(ShadowError::InvalidResolution {
                requested: size.0.max(size.1),
                max: gpu.max_texture_size(),
            });
        }
        let eye = settings.camera.eye;
        let verts: Vec<[f32; 6]> = geometry
            .surfaces()
            .iter()
            .flat_map(|t| {
                let n = (t[1] - t[0]).cross(t[2] - t[0]).normalize_or_zero();
                t.map(|p| [p.x, p.y, p.z, n.x, n.y, n.z])
            })
            .collect();
        let vertices = d.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("renderer vertices"),
            contents: if verts.is_empty() {
                &[0u8; 24]
            } else {
                bytemuck::cast_slice(&verts)
            },
            usage: wgpu::BufferUsages::VERTEX,
        });
        let cam_view: Mat4 = settings
            .camera
            .view(settings.width, settings.height)
            .view_projection();
        let mut cam = cam_view.to_cols_array().to_vec();
        cam.extend_from_slice(&[eye.x, eye.y, eye.z, 1.0]);
        let cam_buf = gpu.uniform_buffer("camera", bytemuck::cast_slice(&cam));
        let gprog = gpu.program(&GBUFFER);
        let camera_bind = d.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("camera"),
            layout: &gprog.layouts[0],
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: cam_buf.as_entire_binding(),
            }],
        });
        let color_target = Some(wgpu::ColorTargetState {
            format: GBUFFER_FORMAT,
            blend: None,
            write_mask: wgpu::ColorWrites::ALL,
        });
        let gbuffer = d.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("gbuffer"),
            layout: Some(&gprog.pipeline_layout),
            vertex: wgpu::VertexState {
                module: &gprog.module,
                entry_point: Some("vs"),
                compilation_options: Default::default(),
                buffers: &[Some(wgpu::VertexBufferLayout {
                    array_stride: 24,
                    step_mode: wgpu::VertexStepMode::Vertex,
                    attributes: &wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3],
                })],
            },
            primitive: wgpu::PrimitiveState::default(),
            // Reversed Z, as `View::view_projection` builds it.
            depth_stencil: Some(wgpu::DepthStencilState {
                format: wgpu::TextureFormat::Depth32Float,
                depth_write_enabled: Some(true),
                depth_compare: Some(wgpu::CompareFunction::Greater),
                stencil: Default::default(),
                bias: Default::default(),
            }),
            multisample: Default::default(),
            fragment: Some(wgpu::FragmentState {
                module: &gprog.module,
                entry_point: Some("fs"),
                compilation_options: Default::default(),
                targets: &[color_target.clone(), color_target],
            }),
            multiview_mask: None,
            cache: None,
        });
        let attach = wgpu::TextureUsages::RENDER_ATTACHMENT
            | wgpu::TextureUsages::TEXTURE_BINDING
            | wgpu::TextureUsages::COPY_SRC;
        let storage = wgpu::TextureUsages::STORAGE_BINDING
            | wgpu::TextureUsages::TEXTURE_BINDING
            | wgpu::TextureUsages::COPY_SRC;
        let targets = Targets {
            position: target(d, "position", size, GBUFFER_FORMAT, attach),
            normal: target(d, "normal", size, GBUFFER_FORMAT, attach),
            depth: target(
                d,
                "depth",
                size,
                wgpu::TextureFormat::Depth32Float,
                wgpu::TextureUsages::RENDER_ATTACHMENT,
            ),
            visibility: target(
                d,
                "visibility",
                size,
                wgpu::TextureFormat::R32Float,
                storage,
            ),
            color: target(d, "color", size, wgpu::TextureFormat::Rgba8Unorm, storage),
        };
        let sprog = gpu.program(&SHADE);
        let shade_pipeline = sprog.compute(&gpu, "shade");
        let shade_uniform = d.create_buffer(&wgpu::BufferDescriptor {
            label: Some("shade"),
            size: std::mem::size_of::<shade::ShadeUniform>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let shade_bind = d.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("shade"),
            layout: &sprog.layouts[0],
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: shade_uniform.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: wgpu::BindingResource::TextureView(&view(&targets.position)),
                },
                wgpu::BindGroupEntry {
                    binding: 2,
                    resource: wgpu::BindingResource::TextureView(&view(&targets.normal)),
                },
                wgpu::BindGroupEntry {
                    binding: 3,
                    resource: wgpu::BindingResource::TextureView(&view(&targets.visibility)),
                },
                wgpu::BindGroupEntry {
                    binding: 4,
                    resource: wgpu::BindingResource::TextureView(&view(&targets.color)),
                },
            ],
        });
        Ok(Self {
            vertex_count: verts.len() as u32,
            gpu,
            technique,
            scene,
            settings,
            vertices,
            camera_bind,
            gbuffer,
            shade_pipeline,
            shade_uniform,
            shade_bind,
            targets,
        })
    }

    /// The technique.
    pub fn technique(&self) -> &T {
        &self.technique
    }

    /// Records one frame lit by `light` into `enc`: G-buffer, shadow maps, `V`, shading.
    /// Nothing is uploaded but parameters, nothing is read back.
    pub fn encode_frame(&self, enc: &mut wgpu::CommandEncoder, light: &Light) -> Result<()> {
        let (gpu, technique, scene) = (&self.gpu, &self.technique, &self.scene);
        let FrameSettings {
            width,
            height,
            resolution,
            ..
        } = self.settings;
        let shade = shade::ShadeUniform::new(light)?;
        gpu.queue
            .write_buffer(&self.shade_uniform, 0, bytemuck::bytes_of(&shade));
        self.encode_gbuffer(enc);
        let (positions, normals) = (view(&self.targets.position), view(&self.targets.normal));
        let visibility = view(&self.targets.visibility);
        // The technique, recorded into the renderer's encoder (the README's snippet).
        let maps = technique.record_gpu(gpu, enc, scene, light, resolution)?;
        let maps_bind = technique.maps_bind_group(gpu, &maps)?;
        technique.record_visibility(
            gpu,
            enc,
            &maps_bind,
            &ReceiverTextures {
                positions: &positions,
                normals: &normals,
                visibility: &visibility,
                size: (width, height),
            },
        );
        // Done reading the maps: their textures serve the next frame's generation.
        technique.recycle_gpu(gpu, maps);
        let mut pass = enc.begin_compute_pass(&Default::default());
        pass.set_pipeline(&self.shade_pipeline);
        pass.set_bind_group(0, &self.shade_bind, &[]);
        pass.dispatch_workgroups(width.div_ceil(8), height.div_ceil(8), 1);
        Ok(())
    }

    /// Records, submits and returns; the frame is in [`Renderer::color`] once the queue has run.
    pub fn render(&self, light: &Light) -> Result<()> {
        self.gpu.checked("frame", || {
            let mut enc = self.gpu.device.create_command_encoder(&Default::default());
            self.encode_frame(&mut enc, light)?;
            self.gpu.queue.submit([enc.finish()]);
            Ok(())
        })
    }

    fn encode_gbuffer(&self, enc: &mut wgpu::CommandEncoder) {
        let (p, n, z) = (
            view(&self.targets.position),
            view(&self.targets.normal),
            view(&self.targets.depth),
        );
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
        let mut rp = enc.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("gbuffer"),
            color_attachments: &[attach(&p), attach(&n)],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: &z,
                depth_ops: Some(wgpu::Operations {
                    load: wgpu::LoadOp::Clear(0.0),
                    store: wgpu::StoreOp::Store,
                }),
                stencil_ops: None,
            }),
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        if self.vertex_count > 0 {
            rp.set_pipeline(&self.gbuffer);
            rp.set_bind_group(0, &self.camera_bind, &[]);
            rp.set_vertex_buffer(0, self.vertices.slice(..));
            rp.draw(0..self.vertex_count, 0..1);
        }
    }

    /// The shaded frame (`Rgba8Unorm`).
    pub fn color(&self) -> &wgpu::Texture {
        &self.targets.color
    }

    /// The G-buffer's position and normal targets (`Rgba32Float`).
    pub fn gbuffer(&self) -> (&wgpu::Texture, &wgpu::Texture) {
        (&self.targets.position, &self.targets.normal)
    }

    /// Reads the shaded frame back (for PNG files and tests; a frame on screen needs no read).
    pub fn read_color(&self) -> Result<image::RgbaImage> {
        let bytes: Vec<[u8; 4]> = soft_shadow_core::gpu::raster::read_texture(
            &self.gpu,
            &self.targets.color,
            0,
            wgpu::TextureAspect::All,
            4,
        )?;
        image::RgbaImage::from_raw(self.settings.width, self.settings.height, bytes.concat())
            .ok_or_else(|| ShadowError::Gpu("frame readback size".into()))
    }
}

/// A glTF model standing on a ground square (which only receives), scaled to fit a 2 m box:
/// the renderer's scene, and a camera looking at it from the front and above.
pub fn model_on_ground(model: &soft_shadow_core::TriangleMesh) -> (SceneGeometry, Camera) {
    let raw: Vec<[Vec3; 3]> = model.world_triangles(Mat4::IDENTITY).collect();
    let b = soft_shadow_core::Aabb::of_triangles(&raw);
    let scale = 2.0 / (b.max - b.min).max_element().max(1e-6);
    let base = Vec3::new(b.center().x, b.min.y, b.center().z);
    let casters: Vec<[Vec3; 3]> = raw.iter().map(|t| t.map(|p| (p - base) * scale)).collect();
    let g = |x: f32, z: f32| Vec3::new(x, 0.0, z);
    let ground = [
        [g(-3.0, -3.0), g(3.0, 3.0), g(3.0, -3.0)],
        [g(-3.0, -3.0), g(-3.0, 3.0), g(3.0, 3.0)],
    ];
    let mut receivers = casters.clone();
    receivers.extend(ground);
    let bounds = soft_shadow_core::Aabb::of_triangles(&receivers);
    let camera = Camera {
        eye: Vec3::new(0.0, 2.6, 4.2),
        target: Vec3::new(0.0, 0.6, 0.0),
        fov_y: 0.9,
        near: 0.1,
        far: 20.0,
    };
    (
        SceneGeometry {
            casters,
            receivers,
            bounds,
        },
        camera,
    )
}

/// Frame `i` of `n`: a 0.6 m square light 3 m up, circling the model once over the frames.
pub fn moving_light(i: u32, n: u32) -> Light {
    let a = std::f32::consts::TAU * i as f32 / n.max(1) as f32;
    Light::Rect {
        center: Vec3::new(1.2 * a.cos(), 3.0, 1.2 * a.sin()),
        u_half: Vec3::X * 0.3,
        v_half: Vec3::Z * 0.3,
    }
}

/// The triangle of the same area and path as [`moving_light`], facing down: for techniques
/// that model triangles but not rectangles (linear-light).
pub fn moving_triangle(i: u32, n: u32) -> Light {
    let Light::Rect { center, .. } = moving_light(i, n) else {
        unreachable!("moving_light is a rectangle")
    };
    // An equilateral triangle of area 0.36 m² centred on the square's centre.
    let side = 0.6 * (4.0 / 3f32.sqrt()).sqrt();
    let (x, z) = (Vec3::X * side, Vec3::Z * side * 3f32.sqrt() / 2.0);
    Light::Triangle {
        a: center - 0.5 * x - z / 3.0,
        b: center + 0.5 * x - z / 3.0,
        c: center + 2.0 * z / 3.0,
    }
}
