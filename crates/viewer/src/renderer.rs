//! The renderer: its own device (wrapped in a [`GpuContext`]), G-buffer and shading passes, and
//! any technique through the public drop-in API. Per frame it records into one encoder its
//! G-buffer pass, each shown technique's generation for the light's views and visibility over
//! the G-buffer from a [`GpuScene`] uploaded once ([`DynTechnique::record_frame`]), and its own
//! shading of the light times `V`; it never reads anything back to draw a frame. A scene of
//! many lamps records the same G-buffer pass ([`Renderer::encode_gbuffer`]) and its own passes
//! ([`crate::lamps::LampsView`]).

use crate::shade::{LampsDisplay, ShadeUniform};
use bytemuck::{Pod, Zeroable};
use glam::{Mat4, Vec3};
use shadow_frame::lighting::LightRecord;
use soft_shadow_core::gpu::shader::{
    Group, Library, Program, ShaderModule, float_texture, storage, storage_texture, uniform,
};
use soft_shadow_core::gpu::visibility::ReceiverTextures;
use soft_shadow_core::gpu::{GpuContext, GpuScene};
use soft_shadow_core::views::ViewSelect;
use soft_shadow_core::{
    Camera, DynTechnique, Light, LightViews, Result, SceneGeometry, SeenDepth, ShadowError,
};
use std::sync::Arc;
use std::time::Instant;
use wgpu::util::DeviceExt;

/// Format of the renderer's position and normal targets.
pub const GBUFFER_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Float;

/// Timestamps [`Renderer::encode_frame`] writes where it is given a query set: before the
/// G-buffer, after it, after the first technique, after the second, after shading.
pub const TIMESTAMPS: u32 = 5;

/// Image size and camera of the renderer's frames.
#[derive(Clone, Copy, Debug)]
pub struct FrameSettings {
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// The camera.
    pub camera: Camera,
}

/// What the frame shows per pixel.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum ViewMode {
    /// Lambert shading times `V`: what a white scene looks like.
    #[default]
    Shaded,
    /// `V` itself, grey.
    Visibility,
    /// `V` against the reference: red where darker (false shadow), blue where lighter (leak),
    /// over the dimmed lit scene.
    Error,
    /// The light's views: each receiver coloured by the view it reads (the frustum, a cube face
    /// or a cascade, [`view_colour`]), blended where neighbouring views share it, times the
    /// shading.
    Views,
}

impl ViewMode {
    /// Every mode.
    pub const ALL: [ViewMode; 4] = [
        ViewMode::Shaded,
        ViewMode::Visibility,
        ViewMode::Error,
        ViewMode::Views,
    ];

    /// Short name (`"shaded"`, `"v"`, `"error"`, `"views"`).
    pub fn name(self) -> &'static str {
        match self {
            ViewMode::Shaded => "shaded",
            ViewMode::Visibility => "v",
            ViewMode::Error => "error",
            ViewMode::Views => "views",
        }
    }
}

/// One technique shown in a frame, at a map side.
#[derive(Clone, Copy)]
pub struct Shadow<'a> {
    /// The technique.
    pub technique: &'a dyn DynTechnique,
    /// Side of its light-space maps.
    pub resolution: u32,
}

/// One frame: the light, the technique (and a second one right of a split column) and the
/// view mode.
#[derive(Clone, Copy)]
pub struct Frame<'a> {
    /// The light.
    pub light: &'a Light,
    /// The technique shown (left of the split).
    pub shadow: Shadow<'a>,
    /// A second technique, shown from pixel column `.1` on.
    pub compare: Option<(Shadow<'a>, u32)>,
    /// What the pixels show.
    pub mode: ViewMode,
}

/// CPU wall time of recording each pass of one frame, milliseconds.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PassTimes {
    /// The G-buffer pass.
    pub gbuffer: f64,
    /// The first technique (generation and `V`).
    pub technique: f64,
    /// The second technique, when one is compared.
    pub compare: f64,
    /// The shading pass.
    pub shade: f64,
}

/// The display uniform, laid out as `Display` in `shade.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
struct DisplayUniform {
    mode: u32,
    split: u32,
    reference: u32,
    line: u32,
    /// How a receiver picks its view of the light ([`ViewMode::Views`]).
    views: ViewSelect,
}

/// The colour of view `i` in [`ViewMode::Views`] (`view_colour` in `shade.wgsl`), cycling
/// after six: red, green, blue, yellow, magenta, cyan.
pub fn view_colour(i: usize) -> Vec3 {
    const COLOURS: [[f32; 3]; 6] = [
        [0.9, 0.2, 0.15],
        [0.2, 0.75, 0.25],
        [0.2, 0.4, 0.95],
        [0.95, 0.85, 0.2],
        [0.85, 0.3, 0.85],
        [0.2, 0.85, 0.9],
    ];
    Vec3::from(COLOURS[i % COLOURS.len()])
}

/// The renderer: its device, its passes, its targets and the scene it draws.
pub struct Renderer {
    /// The renderer's device and queue, as the technique crates take them (shared with a
    /// frame pipeline on the same device, [`crate::lamps::LampsView`]).
    pub gpu: Arc<GpuContext>,
    scene: GpuScene,
    settings: FrameSettings,
    vertices: wgpu::Buffer,
    vertex_count: u32,
    camera_buf: wgpu::Buffer,
    camera_bind: wgpu::BindGroup,
    gbuffer: wgpu::RenderPipeline,
    shade_pipeline: wgpu::ComputePipeline,
    shade_uniform: wgpu::Buffer,
    display_uniform: wgpu::Buffer,
    targets: Targets,
    reference: Option<wgpu::Texture>,
    shade_bind: wgpu::BindGroup,
}

struct Targets {
    position: wgpu::Texture,
    normal: wgpu::Texture,
    depth: wgpu::Texture,
    visibility: [wgpu::Texture; 2],
    color: wgpu::Texture,
    no_reference: wgpu::Texture,
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

impl Targets {
    fn new(d: &wgpu::Device, size: (u32, u32)) -> Self {
        let attach = wgpu::TextureUsages::RENDER_ATTACHMENT
            | wgpu::TextureUsages::TEXTURE_BINDING
            | wgpu::TextureUsages::COPY_SRC;
        let storage = wgpu::TextureUsages::STORAGE_BINDING
            | wgpu::TextureUsages::TEXTURE_BINDING
            | wgpu::TextureUsages::COPY_SRC;
        let vis = |label| target(d, label, size, wgpu::TextureFormat::R32Float, storage);
        Self {
            position: target(d, "position", size, GBUFFER_FORMAT, attach),
            normal: target(d, "normal", size, GBUFFER_FORMAT, attach),
            depth: target(
                d,
                "depth",
                size,
                wgpu::TextureFormat::Depth32Float,
                wgpu::TextureUsages::RENDER_ATTACHMENT,
            ),
            visibility: [vis("visibility"), vis("visibility b")],
            color: target(d, "color", size, wgpu::TextureFormat::Rgba8Unorm, storage),
            no_reference: target(
                d,
                "no reference",
                (1, 1),
                wgpu::TextureFormat::R32Float,
                wgpu::TextureUsages::TEXTURE_BINDING,
            ),
        }
    }
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
                label: Some("viewer"),
                ..Default::default()
            })
            .await
            .map_err(|e| ShadowError::Gpu(format!("request_device: {e}")))
    })
}

/// The renderer's own WGSL, composed by naga_oil like the library's.
pub static SHADERS: Library = Library {
    name: "viewer",
    modules: &[
        ShaderModule {
            path: "viewer::gbuffer",
            source: include_str!("gbuffer.wgsl"),
        },
        ShaderModule {
            path: "viewer::shade",
            source: include_str!("shade.wgsl"),
        },
        ShaderModule {
            path: "viewer::lamps",
            source: include_str!("lamps.wgsl"),
        },
    ],
    depends: &[
        &soft_shadow_core::gpu::shader::SHADERS,
        &shadow_frame::SHADERS,
    ],
    programs: &[&GBUFFER, &SHADE, &LAMPS],
};

/// `gbuffer.wgsl`: the camera (view-projection and eye), read by both stages.
static GBUFFER: Program = Program {
    library: &SHADERS,
    module: "viewer::gbuffer",
    defs: &[],
    groups: &[Group {
        stages: wgpu::ShaderStages::VERTEX_FRAGMENT,
        bindings: &[uniform::<[f32; 20]>()],
    }],
};

/// `shade.wgsl`: the light, the G-buffer and `V`, the colour written, the display settings,
/// the second technique's `V` and the reference.
static SHADE: Program = Program {
    library: &SHADERS,
    module: "viewer::shade",
    defs: &[],
    groups: &[Group::compute(&[
        uniform::<ShadeUniform>(),
        float_texture(wgpu::TextureViewDimension::D2),
        float_texture(wgpu::TextureViewDimension::D2),
        float_texture(wgpu::TextureViewDimension::D2),
        storage_texture(
            wgpu::TextureFormat::Rgba8Unorm,
            wgpu::TextureViewDimension::D2,
        ),
        uniform::<DisplayUniform>(),
        float_texture(wgpu::TextureViewDimension::D2),
        float_texture(wgpu::TextureViewDimension::D2),
    ])],
};

/// `lamps.wgsl`: the lamps, the display, the G-buffer, the lamps' `V` (a layer per lamp) and
/// the colour written ([`crate::lamps::LampsView`]).
pub(crate) static LAMPS: Program = Program {
    library: &SHADERS,
    module: "viewer::lamps",
    defs: &[],
    groups: &[Group::compute(&[
        storage::<LightRecord>(true),
        uniform::<LampsDisplay>(),
        float_texture(wgpu::TextureViewDimension::D2),
        float_texture(wgpu::TextureViewDimension::D2),
        float_texture(wgpu::TextureViewDimension::D2Array),
        storage_texture(
            wgpu::TextureFormat::Rgba8Unorm,
            wgpu::TextureViewDimension::D2,
        ),
    ])],
};

fn camera_data(settings: &FrameSettings) -> Vec<f32> {
    let eye = settings.camera.eye;
    let m: Mat4 = settings
        .camera
        .view(settings.width, settings.height)
        .view_projection();
    let mut cam = m.to_cols_array().to_vec();
    cam.extend_from_slice(&[eye.x, eye.y, eye.z, 1.0]);
    cam
}

impl Renderer {
    /// Builds the passes and targets on the caller's device and uploads `geometry` once (its
    /// surfaces for the renderer's own G-buffer, its casters for the techniques).
    pub fn new(
        device: wgpu::Device,
        queue: wgpu::Queue,
        geometry: &SceneGeometry,
        settings: FrameSettings,
    ) -> Result<Self> {
        let gpu = GpuContext::from_device(device, queue)?;
        let scene = GpuScene::new(&gpu, geometry)?;
        Self::check_size(&gpu, settings.width, settings.height)?;
        let d = &gpu.device;
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
        let camera_buf = d.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("camera"),
            contents: bytemuck::cast_slice(&camera_data(&settings)),
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        });
        let gprog = gpu.program(&GBUFFER);
        let camera_bind = d.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("camera"),
            layout: &gprog.layouts[0],
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: camera_buf.as_entire_binding(),
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
        let targets = Targets::new(d, (settings.width, settings.height));
        let shade_pipeline = gpu.program(&SHADE).compute(&gpu, "shade");
        let uniform_buffer = |label, size| {
            d.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size,
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            })
        };
        let shade_uniform = uniform_buffer("shade", std::mem::size_of::<ShadeUniform>() as u64);
        let display_uniform =
            uniform_buffer("display", std::mem::size_of::<DisplayUniform>() as u64);
        let shade_bind = Self::shade_bind(&gpu, &shade_uniform, &display_uniform, &targets, None);
        Ok(Self {
            vertex_count: verts.len() as u32,
            gpu: Arc::new(gpu),
            scene,
            settings,
            vertices,
            camera_buf,
            camera_bind,
            gbuffer,
            shade_pipeline,
            shade_uniform,
            display_uniform,
            targets,
            reference: None,
            shade_bind,
        })
    }

    fn check_size(gpu: &GpuContext, width: u32, height: u32) -> Result<()> {
        if width == 0 || height == 0 || width.max(height) > gpu.max_texture_size() {
            return Err(ShadowError::InvalidResolution {
                requested: width.max(height),
                max: gpu.max_texture_size(),
            });
        }
        Ok(())
    }

    fn shade_bind(
        gpu: &GpuContext,
        shade: &wgpu::Buffer,
        display: &wgpu::Buffer,
        targets: &Targets,
        reference: Option<&wgpu::Texture>,
    ) -> wgpu::BindGroup {
        let views = [
            view(&targets.position),
            view(&targets.normal),
            view(&targets.visibility[0]),
            view(&targets.color),
            view(&targets.visibility[1]),
            view(reference.unwrap_or(&targets.no_reference)),
        ];
        let entry = |binding, resource| wgpu::BindGroupEntry { binding, resource };
        gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("shade"),
            layout: &gpu.program(&SHADE).layouts[0],
            entries: &[
                entry(0, shade.as_entire_binding()),
                entry(1, wgpu::BindingResource::TextureView(&views[0])),
                entry(2, wgpu::BindingResource::TextureView(&views[1])),
                entry(3, wgpu::BindingResource::TextureView(&views[2])),
                entry(4, wgpu::BindingResource::TextureView(&views[3])),
                entry(5, display.as_entire_binding()),
                entry(6, wgpu::BindingResource::TextureView(&views[4])),
                entry(7, wgpu::BindingResource::TextureView(&views[5])),
            ],
        })
    }

    fn rebind(&mut self) {
        self.shade_bind = Self::shade_bind(
            &self.gpu,
            &self.shade_uniform,
            &self.display_uniform,
            &self.targets,
            self.reference.as_ref(),
        );
    }

    /// The frame settings.
    pub fn settings(&self) -> FrameSettings {
        self.settings
    }

    /// Moves the camera (a uniform write, recorded before the next frame).
    pub fn set_camera(&mut self, camera: Camera) {
        self.settings.camera = camera;
        self.gpu.queue.write_buffer(
            &self.camera_buf,
            0,
            bytemuck::cast_slice(&camera_data(&self.settings)),
        );
    }

    /// Resizes the targets to `width` x `height` (0 or above the device's largest texture is
    /// [`ShadowError::InvalidResolution`], and the targets stay).
    pub fn resize(&mut self, width: u32, height: u32) -> Result<()> {
        Self::check_size(&self.gpu, width, height)?;
        if (width, height) == (self.settings.width, self.settings.height) {
            return Ok(());
        }
        self.targets = Targets::new(&self.gpu.device, (width, height));
        self.settings.width = width;
        self.settings.height = height;
        self.reference = None;
        self.rebind();
        self.set_camera(self.settings.camera);
        Ok(())
    }

    /// Uploads a reference `V` of `width` x `height` (row-major, negative where no light
    /// reaches or nothing is covered) for [`ViewMode::Error`]; `None` removes it.
    pub fn set_reference(&mut self, reference: Option<(u32, u32, &[f32])>) -> Result<()> {
        self.reference = match reference {
            None => None,
            Some((w, h, data)) => {
                if w == 0 || h == 0 || data.len() != (w * h) as usize {
                    return Err(ShadowError::InvalidScene(format!(
                        "a reference of {w}x{h} needs {} values, not {}",
                        w * h,
                        data.len()
                    )));
                }
                Self::check_size(&self.gpu, w, h)?;
                let t = target(
                    &self.gpu.device,
                    "reference",
                    (w, h),
                    wgpu::TextureFormat::R32Float,
                    wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
                );
                self.gpu.queue.write_texture(
                    t.as_image_copy(),
                    bytemuck::cast_slice(data),
                    wgpu::TexelCopyBufferLayout {
                        offset: 0,
                        bytes_per_row: Some(4 * w),
                        rows_per_image: Some(h),
                    },
                    t.size(),
                );
                Some(t)
            }
        };
        self.rebind();
        Ok(())
    }

    /// Records one frame into `enc`: G-buffer, each technique's maps and `V`, shading; writes
    /// [`TIMESTAMPS`] timestamps into `timestamps` where given (the device needs
    /// `TIMESTAMP_QUERY_INSIDE_ENCODERS`). Nothing is uploaded but parameters, nothing is read
    /// back. Returns the CPU time of recording each pass; a technique's typed error (its
    /// light kind, parameters or map side) leaves `enc` partly recorded, to be dropped.
    pub fn encode_frame(
        &self,
        enc: &mut wgpu::CommandEncoder,
        frame: &Frame,
        timestamps: Option<&wgpu::QuerySet>,
    ) -> Result<PassTimes> {
        let width = self.settings.width;
        let stamp = |enc: &mut wgpu::CommandEncoder, i| {
            if let Some(q) = timestamps {
                enc.write_timestamp(q, i);
            }
        };
        let shade = ShadeUniform::new(frame.light)?;
        let (split, line) = match frame.compare {
            Some((_, x)) if x < width => (x, 1),
            _ => (u32::MAX, 0),
        };
        let display = DisplayUniform {
            mode: match frame.mode {
                ViewMode::Shaded => 0,
                ViewMode::Visibility => 1,
                ViewMode::Error => 2,
                ViewMode::Views => 3,
            },
            split,
            reference: self.reference.is_some() as u32,
            line,
            // The views the techniques plan for this frame (`encode_shadow`).
            views: LightViews::plan(frame.light, self.scene.geometry(), self.seen().as_ref())
                .gpu_select(0),
        };
        let q = &self.gpu.queue;
        q.write_buffer(&self.shade_uniform, 0, bytemuck::bytes_of(&shade));
        q.write_buffer(&self.display_uniform, 0, bytemuck::bytes_of(&display));
        let mut times = PassTimes::default();
        let mut clock = Instant::now();
        let mut lap = |t: &mut f64| {
            *t = clock.elapsed().as_secs_f64() * 1e3;
            clock = Instant::now();
        };
        stamp(enc, 0);
        self.encode_gbuffer(enc);
        stamp(enc, 1);
        lap(&mut times.gbuffer);
        let shadows = [Some(frame.shadow), frame.compare.map(|c| c.0)];
        for (k, s) in shadows.iter().enumerate() {
            if let Some(s) = s {
                self.encode_shadow(enc, frame.light, s, k)?;
            }
            stamp(enc, 2 + k as u32);
            if k == 0 {
                lap(&mut times.technique);
            } else if s.is_some() {
                lap(&mut times.compare);
            }
        }
        self.encode_shade(enc);
        stamp(enc, 4);
        lap(&mut times.shade);
        Ok(times)
    }

    /// Records and submits `frame`; it is in [`Renderer::color`] once the queue has run.
    pub fn render(&self, frame: &Frame) -> Result<PassTimes> {
        self.gpu.checked("frame", || {
            let mut enc = self.gpu.device.create_command_encoder(&Default::default());
            let times = self.encode_frame(&mut enc, frame, None)?;
            self.gpu.queue.submit([enc.finish()]);
            Ok(times)
        })
    }

    /// Wall time of each pass of `frame` run alone: each is recorded, submitted and waited for
    /// before the next (for measuring on devices whose timestamps do not separate passes;
    /// nothing a frame on screen does).
    pub fn measure_passes(&self, frame: &Frame) -> Result<PassTimes> {
        // Everything the frame needs written first, the queue idle.
        let mut enc = self.gpu.device.create_command_encoder(&Default::default());
        self.encode_frame(&mut enc, frame, None)?;
        self.gpu.queue.submit([enc.finish()]);
        self.gpu.wait()?;
        let timed = |record: &dyn Fn(&mut wgpu::CommandEncoder) -> Result<()>| -> Result<f64> {
            let start = Instant::now();
            let mut enc = self.gpu.device.create_command_encoder(&Default::default());
            record(&mut enc)?;
            self.gpu.queue.submit([enc.finish()]);
            self.gpu.wait()?;
            Ok(start.elapsed().as_secs_f64() * 1e3)
        };
        let technique =
            |s: Shadow, k: usize| timed(&|enc| self.encode_shadow(enc, frame.light, &s, k));
        Ok(PassTimes {
            gbuffer: timed(&|enc| {
                self.encode_gbuffer(enc);
                Ok(())
            })?,
            technique: technique(frame.shadow, 0)?,
            compare: match frame.compare {
                Some((b, _)) => technique(b, 1)?,
                None => 0.0,
            },
            shade: timed(&|enc| {
                self.encode_shade(enc);
                Ok(())
            })?,
        })
    }

    /// Technique `shadow`'s maps and `V` into visibility target `k`.
    fn encode_shadow(
        &self,
        enc: &mut wgpu::CommandEncoder,
        light: &Light,
        shadow: &Shadow,
        k: usize,
    ) -> Result<()> {
        let (gpu, scene, technique, resolution) =
            (&self.gpu, &self.scene, shadow.technique, shadow.resolution);
        let seen = self.seen();
        let target = &self.targets.visibility[k];
        let (width, height) = (target.width(), target.height());
        let (positions, normals) = (view(&self.targets.position), view(&self.targets.normal));
        let visibility = view(target);
        // The light's views for this camera, then the technique, recorded into the renderer's
        // encoder (the README's snippet).
        let views = LightViews::plan(light, scene.geometry(), seen.as_ref());
        technique.record_frame(
            gpu,
            enc,
            scene,
            light,
            &views,
            resolution,
            &ReceiverTextures {
                positions: &positions,
                normals: &normals,
                visibility: &visibility,
                size: (width, height),
            },
        )?;
        Ok(())
    }

    /// What the camera can see of the scene, for cascades: its view, and the depths from its
    /// near plane to the farthest corner of the scene's bounds in front of it.
    pub fn seen(&self) -> Option<SeenDepth> {
        let camera = self.settings.camera;
        let view = camera.view(self.settings.width, self.settings.height);
        let far = self
            .scene
            .geometry()
            .bounds
            .corners()
            .iter()
            .map(|c| view.linear_depth(*c))
            .fold(0.0f32, f32::max)
            .min(camera.far);
        (far > camera.near).then_some(SeenDepth {
            camera: view,
            near: camera.near,
            far,
        })
    }

    /// The shading and display pass over the whole frame.
    fn encode_shade(&self, enc: &mut wgpu::CommandEncoder) {
        let (w, h) = (self.settings.width, self.settings.height);
        let mut pass = enc.begin_compute_pass(&Default::default());
        pass.set_pipeline(&self.shade_pipeline);
        pass.set_bind_group(0, &self.shade_bind, &[]);
        pass.dispatch_workgroups(w.div_ceil(8), h.div_ceil(8), 1);
    }

    /// The G-buffer pass: the camera's positions and normals into [`Renderer::gbuffer`].
    pub fn encode_gbuffer(&self, enc: &mut wgpu::CommandEncoder) {
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

    /// The shaded frame (`Rgba8Unorm`, the values a PNG stores).
    pub fn color(&self) -> &wgpu::Texture {
        &self.targets.color
    }

    /// The G-buffer's position and normal targets (`Rgba32Float`).
    pub fn gbuffer(&self) -> (&wgpu::Texture, &wgpu::Texture) {
        (&self.targets.position, &self.targets.normal)
    }

    /// Reads the shaded frame back, waiting for the queue (for PNG files and tests; a frame on
    /// screen needs no read).
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
