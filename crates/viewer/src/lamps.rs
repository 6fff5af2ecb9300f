//! The scenes of many lamps ([`soft_shadow_reference::scenes::lamps`]: the night street, the
//! room with three lamps) in the viewer: the frame pipeline (`shadow_frame`) on the renderer's
//! device under one frame budget, each lamp's technique and map side picked by the shared
//! budget, the lamps' maps ([`FramePipeline::run_into`]) and every lamp's `V` over the
//! renderer's G-buffer recorded into the frame's encoder ([`record_visibility`], a layer of one texture per lamp; nothing is read back but the
//! passes' timestamps, [`GpuTiming`]: the budget is in device milliseconds), and a shading pass
//! that sums the lamps (`lamps.wgsl`, mirrored by [`LampShade`]).
//!
//! The pipeline's receivers (what bounds each lamp's maps and weighs its share of the budget)
//! come from a small CPU G-buffer of the same camera and shape ([`receivers_size`]).

use crate::renderer::{LAMPS, PassTimes, Renderer, ViewMode};
use crate::shade::{ALBEDO, BACKGROUND, LAMP_AMBIENT, LampShade, LampsDisplay};
use shadow_frame::RecordedTexels;
use shadow_frame::gpu_frame::{FrameTextures, VisibilityLayer, record_visibility};
use shadow_frame::lighting::LightRecord;
use shadow_frame::scene::LightSource;
use shadow_frame::{
    FrameBackend, FrameBudget, FramePipeline, FrameReceivers, FrameSettings, FrameStats, GpuTiming,
    LightState, ResolvedTechnique, ShadowConfig, ShadowProbe,
};
use soft_shadow_core::gpu::GpuContext;
use soft_shadow_core::{Result, ShadowError};
use soft_shadow_reference::scenes::lamps::{self, Lamps};
use std::sync::Arc;
use std::time::Instant;
use wgpu::util::DeviceExt;

/// Height of the CPU G-buffer whose texels are the pipeline's receivers; its width follows the
/// view's aspect ([`receivers_size`]).
pub const RECEIVERS_HEIGHT: u32 = 90;

/// The CPU G-buffer of the pipeline's receivers for a `width x height` view: the view's shape,
/// [`RECEIVERS_HEIGHT`] high (16 to 1024 wide).
pub fn receivers_size(width: u32, height: u32) -> (u32, u32) {
    let w = (RECEIVERS_HEIGHT as f64 * width as f64 / height.max(1) as f64).round();
    (w.clamp(16.0, 1024.0) as u32, RECEIVERS_HEIGHT)
}

/// The view modes a scene of lamps shows: the shaded frame, and the lamps' `V` weighed by
/// their light; any other mode shows it shaded ([`lamps_mode`]).
pub const MODES: [ViewMode; 2] = [ViewMode::Shaded, ViewMode::Visibility];

/// The mode a scene of lamps shows for `mode` (one of [`MODES`]).
pub fn lamps_mode(mode: ViewMode) -> ViewMode {
    if MODES.contains(&mode) {
        mode
    } else {
        ViewMode::Shaded
    }
}

/// The frame budget a scene of lamps opens with, milliseconds.
pub const BUDGET_MS: f64 = 16.0;

/// One lamp in the panel: what it is and what the budget gave it.
#[derive(Clone, Debug, PartialEq)]
pub struct LampLine {
    /// The light's kind.
    pub kind: &'static str,
    /// Its radiant intensity.
    pub intensity: f32,
    /// Technique, variant and map side, or why it has no shadow.
    pub pick: String,
    /// The profile's prediction of its time, milliseconds.
    pub predicted_ms: Option<f64>,
    /// Its passes' device time in the newest frame whose timestamps came back (generation and
    /// `V`), milliseconds; `None` before any, or without timestamps.
    pub device_ms: Option<f64>,
}

/// A scene of lamps on the renderer's device: the ECS scene, the pipeline, the lamps' `V`
/// texture and the shading pass.
pub struct LampsView {
    /// The scene and its lamps.
    pub lamps: Lamps,
    pipeline: FramePipeline,
    gpu: Arc<GpuContext>,
    shade: LampShade,
    lamp_buffer: wgpu::Buffer,
    display: wgpu::Buffer,
    visibility: wgpu::Texture,
    /// The renderer's colour target [`LampsView::bind`] bound (a resize makes new targets).
    bound: wgpu::Texture,
    bind: wgpu::BindGroup,
    /// Views of the renderer's G-buffer (positions, normals), made with the bound targets: the
    /// pipeline's GPU frame keeps its bind groups while they stay the same views.
    gbuffer: (wgpu::TextureView, wgpu::TextureView),
    shade_pipeline: wgpu::ComputePipeline,
    /// The last frame's pipeline statistics.
    pub stats: Option<FrameStats>,
}

impl LampsView {
    /// The scene of lamps `name` ([`lamps::LAMP_SCENES`]) on `renderer`'s device, under a frame
    /// budget of `budget_ms`, seen by the renderer's camera.
    pub fn new(renderer: &Renderer, name: &str, budget_ms: f64) -> Result<Self> {
        let s = renderer.settings();
        let (w, h) = receivers_size(s.width, s.height);
        let mut lamps = lamps::build(name, w, h, budget_ms)?;
        let gpu = renderer.gpu.clone();
        let world = &mut lamps.scene.world;
        world.insert_resource(FrameBackend::gpu(gpu.clone()));
        world.insert_resource(FrameSettings::default().with_evaluate_receivers(false));
        // The lamps' passes timed on the device: the budget calibrates in device milliseconds.
        world.insert_resource(GpuTiming::default());
        // Each lamp's missing shadow measured at the sampled receivers, as on the CPU.
        world.insert_resource(ShadowProbe::default());
        // The first frame's share already predicts the texels every lamp's `V` covers.
        world.insert_resource(RecordedTexels(s.width as usize * s.height as usize));
        for (k, e) in lamps.lamps.iter().enumerate() {
            world.entity_mut(*e).insert(VisibilityLayer(k as u32));
        }
        let camera = renderer.settings().camera;
        lamps.look(camera);
        let mut shade = LampShade {
            lamps: Self::lamp_data(&lamps),
            exposure: 1.0,
        };
        let frame = lamps.scene.world.resource::<FrameReceivers>();
        shade.expose(&frame.positions, &frame.normals);
        let d = &gpu.device;
        let lamp_buffer = d.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("lamps"),
            contents: bytemuck::cast_slice(&shade.lamps),
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
        });
        let display = d.create_buffer(&wgpu::BufferDescriptor {
            label: Some("lamps display"),
            size: std::mem::size_of::<LampsDisplay>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let visibility = Self::visibility_texture(&gpu, renderer, lamps.lamps.len());
        let bind = Self::bind(&gpu, renderer, &lamp_buffer, &display, &visibility);
        let shade_pipeline = gpu.program(&LAMPS).compute(&gpu, "shade");
        Ok(Self {
            pipeline: FramePipeline::new().with_registry(&soft_shadow_techniques::registry()),
            lamps,
            gpu,
            shade,
            lamp_buffer,
            display,
            visibility,
            bound: renderer.color().clone(),
            bind,
            gbuffer: Self::gbuffer_views(renderer),
            shade_pipeline,
            stats: None,
        })
    }

    fn gbuffer_views(renderer: &Renderer) -> (wgpu::TextureView, wgpu::TextureView) {
        let (position, normal) = renderer.gbuffer();
        (
            position.create_view(&Default::default()),
            normal.create_view(&Default::default()),
        )
    }

    fn lamp_data(lamps: &Lamps) -> Vec<LightRecord> {
        let world = &lamps.scene.world;
        lamps
            .lamps
            .iter()
            .map(|&e| {
                let light = world.get::<LightSource>(e).map(|l| l.0);
                let config = world.get::<ShadowConfig>(e);
                match (light, config) {
                    (Some(l), Some(c)) => LightRecord::of(&l, c),
                    _ => LightRecord::default(),
                }
            })
            .collect()
    }

    fn visibility_texture(gpu: &GpuContext, renderer: &Renderer, layers: usize) -> wgpu::Texture {
        let s = renderer.settings();
        gpu.device.create_texture(&wgpu::TextureDescriptor {
            label: Some("lamps visibility"),
            size: wgpu::Extent3d {
                width: s.width,
                height: s.height,
                depth_or_array_layers: layers.max(1) as u32,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: wgpu::TextureFormat::R32Float,
            usage: wgpu::TextureUsages::STORAGE_BINDING
                | wgpu::TextureUsages::TEXTURE_BINDING
                | wgpu::TextureUsages::COPY_DST
                | wgpu::TextureUsages::COPY_SRC,
            view_formats: &[],
        })
    }

    fn bind(
        gpu: &GpuContext,
        renderer: &Renderer,
        lamps: &wgpu::Buffer,
        display: &wgpu::Buffer,
        visibility: &wgpu::Texture,
    ) -> wgpu::BindGroup {
        let (position, normal) = renderer.gbuffer();
        let views = [
            position.create_view(&Default::default()),
            normal.create_view(&Default::default()),
            visibility.create_view(&wgpu::TextureViewDescriptor {
                dimension: Some(wgpu::TextureViewDimension::D2Array),
                ..Default::default()
            }),
            renderer.color().create_view(&Default::default()),
        ];
        let entry = |binding, resource| wgpu::BindGroupEntry { binding, resource };
        gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("lamps shade"),
            layout: &gpu.program(&LAMPS).layouts[0],
            entries: &[
                entry(0, lamps.as_entire_binding()),
                entry(1, display.as_entire_binding()),
                entry(2, wgpu::BindingResource::TextureView(&views[0])),
                entry(3, wgpu::BindingResource::TextureView(&views[1])),
                entry(4, wgpu::BindingResource::TextureView(&views[2])),
                entry(5, wgpu::BindingResource::TextureView(&views[3])),
            ],
        })
    }

    /// The frame budget shared by the lamps, milliseconds.
    pub fn budget_ms(&self) -> f64 {
        self.lamps.scene.world.resource::<FrameBudget>().ms
    }

    /// Shares `ms` among the lamps from the next frame on (a positive, finite number; anything
    /// else is [`ShadowError::InvalidParameter`]).
    pub fn set_budget_ms(&mut self, ms: f64) -> Result<()> {
        if !(ms.is_finite() && ms > 0.0) {
            return Err(ShadowError::InvalidParameter(format!(
                "a frame budget of {ms} ms"
            )));
        }
        let world = &mut self.lamps.scene.world;
        if world.resource::<FrameBudget>().ms != ms {
            world.insert_resource(FrameBudget { ms });
        }
        Ok(())
    }

    /// The shading the pass applies (for comparing it with the CPU).
    pub fn shade(&self) -> &LampShade {
        &self.shade
    }

    /// The texture of the lamps' `V`, layer `k` lamp `k`'s (`R32Float`, the view's size).
    pub fn visibility(&self) -> &wgpu::Texture {
        &self.visibility
    }

    /// Records one frame into `enc`: the renderer's G-buffer, the pipeline's frame for the
    /// renderer's camera (the maps of the lamps whose maps are stale, made on the device), each
    /// lamp's `V` into its layer and the shading into [`Renderer::color`]. `swing`, where given,
    /// is the frame of [`Lamps::swing`]'s swing. `mode` [`ViewMode::Visibility`] shows the
    /// lamps' `V` weighed by their light; every other mode the shaded frame ([`lamps_mode`]).
    /// Writes [`crate::renderer::TIMESTAMPS`] timestamps into `timestamps` where given, as
    /// [`Renderer::encode_frame`] does: the lamps' `V` passes stand as the technique (the maps
    /// the pipeline makes are its own submissions), none as the compared one. Returns the CPU
    /// time of each part: the G-buffer, the pipeline and the lamps' `V` (as the technique),
    /// and the shading.
    pub fn encode(
        &mut self,
        renderer: &Renderer,
        enc: &mut wgpu::CommandEncoder,
        mode: ViewMode,
        swing: Option<u32>,
        timestamps: Option<&wgpu::QuerySet>,
    ) -> Result<PassTimes> {
        let stamp = |enc: &mut wgpu::CommandEncoder, i| {
            if let Some(q) = timestamps {
                enc.write_timestamp(q, i);
            }
        };
        let mut times = PassTimes::default();
        let mut clock = Instant::now();
        let mut lap = |t: &mut f64| {
            *t = clock.elapsed().as_secs_f64() * 1e3;
            clock = Instant::now();
        };
        let s = renderer.settings();
        if renderer.color() != &self.bound {
            // The renderer was resized: its targets are new, and the receivers take the
            // view's shape.
            if (self.visibility.width(), self.visibility.height()) != (s.width, s.height) {
                self.visibility =
                    Self::visibility_texture(&self.gpu, renderer, self.lamps.lamps.len());
            }
            let (w, h) = receivers_size(s.width, s.height);
            if self.lamps.size() != (w, h) {
                self.lamps.resize(w, h);
            }
            self.bound = renderer.color().clone();
            self.gbuffer = Self::gbuffer_views(renderer);
            self.bind = Self::bind(
                &self.gpu,
                renderer,
                &self.lamp_buffer,
                &self.display,
                &self.visibility,
            );
        }
        stamp(enc, 0);
        renderer.encode_gbuffer(enc);
        stamp(enc, 1);
        lap(&mut times.gbuffer);
        if s.camera != self.lamps.camera {
            self.lamps.look(s.camera);
        }
        if let Some(f) = swing {
            self.lamps.swing(f);
        }
        // The lamps' maps are recorded into this frame's encoder, before their `V`.
        let stats = self.pipeline.run_into(&mut self.lamps.scene.world, enc)?;
        record_visibility(
            &mut self.lamps.scene.world,
            &self.gpu,
            enc,
            &FrameTextures {
                positions: &self.gbuffer.0,
                normals: &self.gbuffer.1,
                visibility: &self.visibility,
            },
        )?;
        self.stats = Some(stats);
        stamp(enc, 2);
        stamp(enc, 3);
        lap(&mut times.technique);
        let data = Self::lamp_data(&self.lamps);
        if data != self.shade.lamps {
            self.shade.lamps = data;
            self.gpu.queue.write_buffer(
                &self.lamp_buffer,
                0,
                bytemuck::cast_slice(&self.shade.lamps),
            );
        }
        let display = LampsDisplay {
            count: self.shade.lamps.len() as u32,
            mode: u32::from(lamps_mode(mode) == ViewMode::Visibility),
            pad: [0; 2],
            terms: [self.shade.exposure, LAMP_AMBIENT, ALBEDO, BACKGROUND],
        };
        self.gpu
            .queue
            .write_buffer(&self.display, 0, bytemuck::bytes_of(&display));
        {
            let mut pass = enc.begin_compute_pass(&Default::default());
            pass.set_pipeline(&self.shade_pipeline);
            pass.set_bind_group(0, &self.bind, &[]);
            pass.dispatch_workgroups(s.width.div_ceil(8), s.height.div_ceil(8), 1);
        }
        stamp(enc, 4);
        lap(&mut times.shade);
        Ok(times)
    }

    /// Call after submitting the encoder [`LampsView::encode`] recorded into: asks for the
    /// lamps' device times and their probed `V` back ([`shadow_frame::gpu_frame::submitted`]).
    pub fn submitted(&mut self) {
        shadow_frame::gpu_frame::submitted(&mut self.lamps.scene.world);
    }

    /// Every lamp's line for the panel, in layer order.
    pub fn lines(&self) -> Vec<LampLine> {
        let world = &self.lamps.scene.world;
        self.lamps
            .lamps
            .iter()
            .map(|&e| {
                let light = world.get::<LightSource>(e).map(|l| l.0);
                let state = world.get::<LightState>(e);
                let pick = match (
                    world.get::<ResolvedTechnique>(e),
                    state.and_then(|s| s.error.as_ref()),
                ) {
                    (_, Some(why)) => format!("no shadow: {why}"),
                    (Some(r), None) => format!(
                        "{} {} {}²",
                        r.technique.name(),
                        r.technique.variant(),
                        r.resolution
                    ),
                    (None, None) => "no shadow: lights nothing in view".into(),
                };
                let predicted_ms = self
                    .stats
                    .as_ref()
                    .and_then(|s| s.lights.iter().find(|l| l.light == e))
                    .and_then(|l| l.predicted_ms);
                let device_ms = world
                    .get_resource::<GpuTiming>()
                    .and_then(GpuTiming::latest)
                    .and_then(|t| t.lights.iter().find(|l| l.light == e))
                    .and_then(|l| match (l.generate_ms, l.evaluate_ms) {
                        (None, None) => None,
                        (g, v) => Some(g.unwrap_or(0.0) + v.unwrap_or(0.0)),
                    });
                LampLine {
                    kind: light.map_or("?", |l| l.kind().name()),
                    intensity: world.get::<ShadowConfig>(e).map_or(0.0, |c| c.intensity),
                    pick,
                    predicted_ms,
                    device_ms,
                }
            })
            .collect()
    }
}
