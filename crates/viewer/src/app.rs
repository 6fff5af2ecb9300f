//! The window: winit 0.30 events, egui 0.37 panels, the surface, and the frame loop. Nothing on
//! the UI thread waits for the reference or for a readback: both arrive through channels and
//! buffer-mapping callbacks polled once per frame.

use crate::lamps::LampsView;
use crate::reference::{ReferenceKey, References};
use crate::renderer::{Frame, FrameSettings, PassTimes, Renderer, Shadow, TIMESTAMPS, ViewMode};
use crate::scene::{LoadedScene, SceneSource, load};
use crate::state::{Choice, ViewState};
use crate::ui::{Actions, LampsPanel, Model, panel};
pub use crate::ui::{PANEL_WIDTH, Stats};
use soft_shadow_core::{DeviceLimits, LightKind, Registry, Technique};
use std::collections::VecDeque;
use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};
use std::time::Instant;
use winit::application::ApplicationHandler;
use winit::event::WindowEvent;
use winit::event_loop::{ActiveEventLoop, EventLoop};
use winit::window::{Window, WindowId};

/// Frame times the graph keeps.
const HISTORY: usize = 240;

/// What the viewer opens with, and the command-line mode.
#[derive(Clone, Debug)]
pub struct Options {
    /// The scene.
    pub scene: SceneSource,
    /// Technique name.
    pub technique: String,
    /// Its variant (the default where `None`).
    pub variant: Option<String>,
    /// A second technique, shown right of the split.
    pub compare: Option<String>,
    /// Map side.
    pub resolution: u32,
    /// Size of the 3D view in pixels (the window adds the panel).
    pub view_size: (u32, u32),
    /// What the view shows.
    pub mode: ViewMode,
    /// Whether the light turns.
    pub animate: bool,
    /// The light's kind, where not the scene's own.
    pub light: Option<LightKind>,
    /// Command-line mode: render this many frames, then exit.
    pub frames: Option<u32>,
    /// Command-line mode: write the last frame (the whole window) to this PNG.
    pub screenshot: Option<PathBuf>,
    /// The frame budget the lamps of a scene of lamps share, milliseconds.
    pub budget_ms: f64,
}

/// Opens the window and runs until it closes (or, in command-line mode, until the frames are
/// drawn and the screenshot written). The scene is opened first: a file that cannot be read is
/// an error before any window opens.
pub fn run(options: Options) -> Result<(), String> {
    run_with(options, soft_shadow_techniques::registry())
}

/// [`run`] offering the techniques of `registry` (the viewer's own is
/// `soft_shadow_techniques::registry()`).
pub fn run_with(options: Options, registry: Registry) -> Result<(), String> {
    let scene = load(&options.scene).map_err(|e| format!("cannot open the scene: {e}"))?;
    let mut shadow = Choice::new(&registry, &options.technique, options.resolution)
        .map_err(|e| e.to_string())?;
    if let Some(v) = &options.variant {
        let e = registry
            .family(&options.technique)
            .map_err(|e| e.to_string())?;
        if e.variant(v).is_none() {
            let labels: Vec<String> = e.variants().map(|t| t.variant()).collect();
            return Err(format!(
                "{} has no variant {v:?}; one of {}",
                e.name(),
                labels.join(", ")
            ));
        }
        shadow.variant = v.clone();
    }
    let mut state = ViewState::new(&scene.camera, &scene.light, shadow);
    state.mode = match scene.lamps {
        Some(_) => crate::lamps::lamps_mode(options.mode),
        None => options.mode,
    };
    state.animate = options.animate;
    if let Some(kind) = options.light
        && kind != state.light.kind
    {
        state.light.kind = kind;
        state.scene_light = None;
    }
    if let Some(name) = &options.compare {
        state.compare =
            Some(Choice::new(&registry, name, options.resolution).map_err(|e| e.to_string())?);
    }
    for choice in std::iter::once(&state.shadow).chain(state.compare.as_ref()) {
        registry
            .family(choice.technique)
            .map_err(|e| e.to_string())?
            .availability(state.light.kind)?;
    }
    let event_loop = EventLoop::new().map_err(|e| format!("cannot open a window: {e}"))?;
    let mut app = App {
        model: Model {
            registry,
            state,
            messages: VecDeque::new(),
            file_field: String::new(),
            scene_name: scene.name.clone(),
            view_px: options.view_size,
            view_origin_px: (0, 0),
            stats: Stats::default(),
            actions: Actions::default(),
            reference_status: String::new(),
            lost: None,
            timestamps: false,
            device: DeviceLimits {
                max_texture_side: 8192,
                max_storage_buffer_bytes: 128 << 20,
            },
            lamps: scene
                .lamps
                .as_ref()
                .map(|_| LampsPanel::new(options.budget_ms)),
        },
        scene,
        scene_id: 0,
        gfx: None,
        references: References::new(),
        options,
        frames_drawn: 0,
        last_frame: Instant::now(),
        status: Ok(()),
        screenshot: None,
        exiting: false,
        reference_shown: None,
    };
    event_loop
        .run_app(&mut app)
        .map_err(|e| format!("the event loop failed: {e}"))?;
    app.status
}

struct Timestamps {
    set: wgpu::QuerySet,
    resolve: wgpu::Buffer,
    /// Readback buffers: the buffer, mapped, in flight, and whether its frame compared two
    /// techniques.
    readback: Vec<(wgpu::Buffer, Arc<AtomicBool>, bool, bool)>,
    period_ns: f32,
}

struct Screenshot {
    buffer: wgpu::Buffer,
    ready: Arc<AtomicBool>,
    size: (u32, u32),
    row: u32,
    bgra: bool,
    path: PathBuf,
}

struct Gfx {
    window: Arc<Window>,
    surface: wgpu::Surface<'static>,
    config: wgpu::SurfaceConfiguration,
    device: wgpu::Device,
    queue: wgpu::Queue,
    renderer: Renderer,
    egui: egui::Context,
    egui_state: egui_winit::State,
    egui_renderer: egui_wgpu::Renderer,
    view_texture: egui::TextureId,
    timestamps: Option<Timestamps>,
    /// A scene of lamps' frame pipeline and shading, drawn instead of one light's technique.
    lamps: Option<LampsView>,
    errors: Arc<Mutex<Vec<String>>>,
    lost: Arc<Mutex<Option<String>>>,
}

/// The techniques, light and mode of one frame, owned.
struct Shown {
    light: soft_shadow_core::Light,
    technique: Technique,
    resolution: u32,
    compare: Option<(Technique, u32, u32)>,
    mode: ViewMode,
}

impl Shown {
    fn frame(&self) -> Frame<'_> {
        Frame {
            light: &self.light,
            shadow: Shadow {
                technique: self.technique.as_ref(),
                resolution: self.resolution,
            },
            compare: self.compare.as_ref().map(|(t, resolution, x)| {
                (
                    Shadow {
                        technique: t.as_ref(),
                        resolution: *resolution,
                    },
                    *x,
                )
            }),
            mode: self.mode,
        }
    }
}

struct App {
    model: Model,
    scene: LoadedScene,
    scene_id: u64,
    gfx: Option<Gfx>,
    references: References,
    options: Options,
    frames_drawn: u32,
    last_frame: Instant,
    status: Result<(), String>,
    screenshot: Option<Screenshot>,
    exiting: bool,
    /// The reference pass the renderer holds ([`References::current_pass`]).
    reference_shown: Option<(u64, usize)>,
}

impl ApplicationHandler for App {
    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        if self.gfx.is_some() {
            return;
        }
        match self.create_gfx(event_loop) {
            Ok(g) => {
                self.references
                    .set_scene(self.scene_id, self.scene.geometry.clone());
                self.gfx = Some(g);
            }
            Err(e) => self.fail(event_loop, e),
        }
    }

    fn window_event(&mut self, event_loop: &ActiveEventLoop, _id: WindowId, event: WindowEvent) {
        let Some(gfx) = self.gfx.as_mut() else {
            return;
        };
        let response = gfx.egui_state.on_window_event(&gfx.window, &event);
        match event {
            WindowEvent::CloseRequested => event_loop.exit(),
            WindowEvent::Resized(size) => {
                gfx.config.width = size.width.max(1);
                gfx.config.height = size.height.max(1);
                gfx.surface.configure(&gfx.device, &gfx.config);
            }
            WindowEvent::DroppedFile(path) => {
                self.model.actions.open = Some(SceneSource::File(path));
            }
            WindowEvent::RedrawRequested => self.redraw(event_loop),
            _ => {}
        }
        if response.repaint
            && let Some(g) = &self.gfx
        {
            g.window.request_redraw();
        }
    }

    fn about_to_wait(&mut self, _event_loop: &ActiveEventLoop) {
        if let Some(g) = &self.gfx {
            g.window.request_redraw();
        }
    }
}

impl App {
    /// Ends the run with `message` (`main` prints it).
    fn fail(&mut self, event_loop: &ActiveEventLoop, message: String) {
        self.status = Err(message);
        self.exiting = true;
        event_loop.exit();
    }

    fn create_gfx(&mut self, event_loop: &ActiveEventLoop) -> Result<Gfx, String> {
        let (vw, vh) = self.options.view_size;
        let attrs = Window::default_attributes()
            .with_title("soft shadows")
            .with_inner_size(winit::dpi::PhysicalSize::new(vw + PANEL_WIDTH as u32, vh));
        let window = Arc::new(
            event_loop
                .create_window(attrs)
                .map_err(|e| format!("cannot open a window: {e}"))?,
        );
        let instance =
            wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle_from_env());
        let surface = instance
            .create_surface(window.clone())
            .map_err(|e| format!("cannot draw into the window: {e}"))?;
        let adapter = pollster::block_on(instance.request_adapter(&wgpu::RequestAdapterOptions {
            compatible_surface: Some(&surface),
            ..Default::default()
        }))
        .map_err(|e| format!("no GPU adapter can draw into the window: {e}"))?;
        let wanted =
            wgpu::Features::TIMESTAMP_QUERY | wgpu::Features::TIMESTAMP_QUERY_INSIDE_ENCODERS;
        let features = adapter.features() & wanted;
        let mut limits = soft_shadow_core::GpuContext::required_limits();
        limits.max_texture_dimension_2d = adapter.limits().max_texture_dimension_2d;
        let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
            label: Some("viewer"),
            required_features: features,
            required_limits: limits,
            ..Default::default()
        }))
        .map_err(|e| format!("cannot open the GPU device: {e}"))?;
        // Errors and a lost device are reported in the panel, never a panic.
        let errors = Arc::new(Mutex::new(Vec::new()));
        let sink = errors.clone();
        device.on_uncaptured_error(Arc::new(move |e: wgpu::Error| {
            if let Ok(mut v) = sink.lock() {
                v.push(format!("GPU error: {e}"));
            }
        }));
        let lost = Arc::new(Mutex::new(None));
        let sink = lost.clone();
        device.set_device_lost_callback(move |reason, message| {
            if let Ok(mut l) = sink.lock() {
                *l = Some(format!("the GPU device was lost ({reason:?}): {message}"));
            }
        });
        let caps = surface.get_capabilities(&adapter);
        // A format without sRGB encoding: the frame's bytes are what a PNG stores.
        let format = caps
            .formats
            .iter()
            .copied()
            .find(|f| {
                matches!(
                    f,
                    wgpu::TextureFormat::Bgra8Unorm | wgpu::TextureFormat::Rgba8Unorm
                )
            })
            .ok_or_else(|| {
                format!(
                    "the window offers no 8-bit UNORM format: {:?}",
                    caps.formats
                )
            })?;
        let size = window.inner_size();
        let config = wgpu::SurfaceConfiguration {
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT,
            format,
            width: size.width.max(1),
            height: size.height.max(1),
            present_mode: wgpu::PresentMode::AutoVsync,
            desired_maximum_frame_latency: 2,
            alpha_mode: caps.alpha_modes[0],
            view_formats: vec![],
            color_space: wgpu::SurfaceColorSpace::Auto,
        };
        surface.configure(&device, &config);
        let renderer = Renderer::new(
            device.clone(),
            queue.clone(),
            &self.scene.geometry,
            FrameSettings {
                width: vw,
                height: vh,
                camera: self.model.state.camera.camera(),
            },
        )
        .map_err(|e| format!("cannot build the renderer: {e}"))?;
        let lamps = match &self.scene.lamps {
            Some(name) => Some(
                LampsView::new(&renderer, name, self.options.budget_ms)
                    .map_err(|e| format!("cannot shade {name}'s lamps: {e}"))?,
            ),
            None => None,
        };
        let egui = egui::Context::default();
        let egui_state = egui_winit::State::new(
            egui.clone(),
            egui::ViewportId::ROOT,
            &window,
            Some(window.scale_factor() as f32),
            None,
            Some(device.limits().max_texture_dimension_2d as usize),
        );
        let mut egui_renderer = egui_wgpu::Renderer::new(
            &device,
            format,
            egui_wgpu::RendererOptions {
                dithering: false,
                ..Default::default()
            },
        );
        let view_texture = egui_renderer.register_native_texture(
            &device,
            &renderer.color().create_view(&Default::default()),
            wgpu::FilterMode::Nearest,
        );
        let timestamps = features.contains(wanted).then(|| {
            let bytes = 8 * TIMESTAMPS as u64;
            let buffer = |label, usage| {
                device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some(label),
                    size: bytes,
                    usage,
                    mapped_at_creation: false,
                })
            };
            Timestamps {
                set: device.create_query_set(&wgpu::QuerySetDescriptor {
                    label: Some("pass timestamps"),
                    ty: wgpu::QueryType::Timestamp,
                    count: TIMESTAMPS,
                }),
                resolve: buffer(
                    "timestamps",
                    wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
                ),
                readback: (0..3)
                    .map(|_| {
                        (
                            buffer(
                                "timestamps readback",
                                wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
                            ),
                            Arc::new(AtomicBool::new(false)),
                            false,
                            false,
                        )
                    })
                    .collect(),
                period_ns: queue.get_timestamp_period(),
            }
        });
        self.model.timestamps = timestamps.is_some();
        self.model.device = DeviceLimits::from_limits(&device.limits());
        Ok(Gfx {
            window,
            surface,
            config,
            device,
            queue,
            renderer,
            egui,
            egui_state,
            egui_renderer,
            view_texture,
            timestamps,
            lamps,
            errors,
            lost,
        })
    }

    /// Opens `source` on the current device; on failure the message goes to the panel and the
    /// previous scene stays.
    fn open(&mut self, source: SceneSource) {
        let Some(gfx) = self.gfx.as_mut() else {
            return;
        };
        let budget_ms = self
            .model
            .lamps
            .as_ref()
            .map_or(self.options.budget_ms, |l| l.budget_ms);
        let opened = load(&source).and_then(|scene| {
            let renderer = Renderer::new(
                gfx.device.clone(),
                gfx.queue.clone(),
                &scene.geometry,
                FrameSettings {
                    width: self.model.view_px.0.max(1),
                    height: self.model.view_px.1.max(1),
                    camera: scene.camera,
                },
            )?;
            let lamps = match &scene.lamps {
                Some(name) => Some(LampsView::new(&renderer, name, budget_ms)?),
                None => None,
            };
            Ok((scene, renderer, lamps))
        });
        match opened {
            Ok((scene, renderer, lamps)) => {
                gfx.renderer = renderer;
                self.model.lamps = lamps.as_ref().map(|_| LampsPanel::new(budget_ms));
                gfx.lamps = lamps;
                gfx.egui_renderer.update_egui_texture_from_wgpu_texture(
                    &gfx.device,
                    &gfx.renderer.color().create_view(&Default::default()),
                    wgpu::FilterMode::Nearest,
                    gfx.view_texture,
                );
                let m = &mut self.model;
                let (shadow, compare, mode) = (
                    m.state.shadow.clone(),
                    m.state.compare.clone(),
                    m.state.mode,
                );
                m.state = ViewState::new(&scene.camera, &scene.light, shadow);
                m.state.compare = compare;
                m.state.mode = match scene.lamps {
                    Some(_) => crate::lamps::lamps_mode(mode),
                    None => mode,
                };
                let kind = m.state.light.kind;
                for line in m.state.set_light_kind(kind, &m.registry) {
                    m.say(line);
                }
                m.scene_name = scene.name.clone();
                m.say(format!("opened {}", scene.name));
                self.scene_id += 1;
                self.references
                    .set_scene(self.scene_id, scene.geometry.clone());
                self.scene = scene;
            }
            Err(e) => self.model.say(format!("cannot open the scene: {e}")),
        }
    }

    fn technique(&self, choice: &Choice) -> Option<Technique> {
        let e = self.model.registry.family(choice.technique).ok()?;
        e.variant(&choice.variant).cloned()
    }

    fn poll_readbacks(&mut self, event_loop: &ActiveEventLoop) {
        let Some(gfx) = self.gfx.as_mut() else {
            return;
        };
        let _ = gfx.device.poll(wgpu::PollType::Poll);
        if let Some(ts) = gfx.timestamps.as_mut() {
            for (buffer, ready, pending, compared) in &mut ts.readback {
                if *pending && ready.load(Ordering::Acquire) {
                    let t: Vec<u64> = match buffer.slice(..).get_mapped_range() {
                        Ok(view) => bytemuck::cast_slice(&view).to_vec(),
                        Err(_) => vec![0; TIMESTAMPS as usize],
                    };
                    buffer.unmap();
                    *pending = false;
                    ready.store(false, Ordering::Release);
                    let ms = |a: usize| {
                        t[a + 1].saturating_sub(t[a]) as f64 * ts.period_ns as f64 * 1e-6
                    };
                    // Without a second technique its two timestamps are adjacent; a queue
                    // that writes timestamps late (lavapipe) would charge the first
                    // technique's work to the empty slot, so both count as the technique.
                    let gpu = if *compared {
                        [ms(0), ms(1), ms(2), ms(3)]
                    } else {
                        [ms(0), ms(1) + ms(2), 0.0, ms(3)]
                    };
                    self.model.stats.gpu_ms = Some(gpu);
                    if let Some(last) = self.model.stats.log.last_mut() {
                        last.1 = Some(gpu);
                    }
                }
            }
        }
        if let Some(shot) = self.screenshot.take_if(|s| s.ready.load(Ordering::Acquire)) {
            match write_screenshot(&shot) {
                Ok(()) => {
                    let msg = format!("wrote {}", shot.path.display());
                    println!("{msg}");
                    self.model.say(msg);
                }
                Err(e) => {
                    self.model.say(e.clone());
                    if self.options.frames.is_some() {
                        self.fail(event_loop, e);
                    }
                }
            }
            if self.options.frames.is_some() && !self.exiting {
                self.finish(event_loop);
            }
        }
    }

    /// Command-line mode is done: print where the view was and what the frames cost (and each
    /// pass run alone, median of three), exit.
    fn finish(&mut self, event_loop: &ActiveEventLoop) {
        self.exiting = true;
        let m = &self.model;
        println!(
            "view {}x{} at {},{} in the window",
            m.view_px.0, m.view_px.1, m.view_origin_px.0, m.view_origin_px.1
        );
        if let Some(l) = &m.lamps {
            print!("{}{}", l.summary(&m.stats), pass_summary(&m.stats));
        } else {
            print!("{}", summary(&m.stats, &m.state));
        }
        if let (Some(gfx), Ok(shown), None) = (
            &self.gfx,
            self.shown(self.model.view_px.0),
            &self.model.lamps,
        ) {
            let runs: Vec<PassTimes> = (0..3)
                .filter_map(|_| gfx.renderer.measure_passes(&shown.frame()).ok())
                .collect();
            let med = |f: fn(&PassTimes) -> f64| median(runs.iter().map(f).collect());
            println!(
                "  each pass alone (submitted and waited for), median of {}, ms: gbuffer {:.1}, \
                 technique {:.1}, compared {:.1}, shading {:.1}",
                runs.len(),
                med(|p| p.gbuffer),
                med(|p| p.technique),
                med(|p| p.compare),
                med(|p| p.shade)
            );
        }
        event_loop.exit();
    }

    /// What the view shows this frame: the light, the techniques, the split in a view `width`
    /// pixels wide (an error says what is missing).
    fn shown(&self, width: u32) -> Result<Shown, String> {
        let state = &self.model.state;
        let light = state.frame_light().map_err(|e| e.to_string())?;
        let a = self.technique(&state.shadow).ok_or_else(|| {
            format!(
                "no variant {} of {}",
                state.shadow.variant, state.shadow.technique
            )
        })?;
        let compare = match (&state.compare, state.split_column(width)) {
            (Some(c), Some(x)) => self.technique(c).map(|t| (t, c.resolution, x)),
            _ => None,
        };
        Ok(Shown {
            light,
            technique: a,
            resolution: state.shadow.resolution,
            compare,
            mode: state.mode,
        })
    }

    fn redraw(&mut self, event_loop: &ActiveEventLoop) {
        if self.exiting {
            return;
        }
        let now = Instant::now();
        let dt = now.duration_since(self.last_frame).as_secs_f32();
        self.last_frame = now;
        {
            let s = &mut self.model.stats;
            s.frame_ms.push_back(dt * 1e3);
            while s.frame_ms.len() > HISTORY {
                s.frame_ms.pop_front();
            }
        }
        if self.model.state.animate {
            self.model.state.time += if self.options.frames.is_some() {
                1.0 / 60.0
            } else {
                dt
            };
        }
        self.poll_readbacks(event_loop);
        if self.exiting {
            return;
        }
        let Some(gfx) = self.gfx.as_mut() else {
            return;
        };
        if let Ok(mut e) = gfx.errors.lock() {
            for m in e.drain(..) {
                self.model.say(m);
            }
        }
        if let Some(l) = gfx.lost.lock().ok().and_then(|l| l.clone()) {
            if self.model.lost.is_none() {
                eprintln!("error: {l}");
                self.model.lost = Some(l.clone());
                gfx.window.set_title(&format!("soft shadows: {l}"));
                if self.options.frames.is_some() {
                    self.fail(event_loop, l);
                }
            }
            return;
        }
        // The reference, when the view shows the error.
        let light = self.model.state.frame_light();
        if self.model.state.mode == ViewMode::Error && self.model.lamps.is_none() {
            if let Ok(light) = light {
                let (w, h) = (
                    gfx.renderer.settings().width,
                    gfx.renderer.settings().height,
                );
                self.references.request(ReferenceKey {
                    scene: self.scene_id,
                    light,
                    camera: self.model.state.camera.camera(),
                    width: w,
                    height: h,
                });
            }
            self.references.poll();
            // Uploaded only when the pass shown changes (a new key, or a finer pass).
            let shown = self.references.current_pass();
            if shown != self.reference_shown {
                self.reference_shown = shown;
                let r = self.references.current();
                let upload = r.map(|r| (r.width, r.height, r.data.as_slice()));
                if let Err(e) = gfx.renderer.set_reference(upload) {
                    self.model.say(format!("reference: {e}"));
                }
            }
            self.model.reference_status = self.references.status();
        }
        // The panel.
        let raw = gfx.egui_state.take_egui_input(&gfx.window);
        let model = &mut self.model;
        let tex = gfx.view_texture;
        let tex_size = (
            gfx.renderer.settings().width,
            gfx.renderer.settings().height,
        );
        let edit = model.state.light;
        let output = gfx.egui.run_ui(raw, |ui| panel(ui, model, tex, tex_size));
        if model.state.light != edit {
            // Edited: from now on the light is the edit's.
            model.state.scene_light = None;
        }
        gfx.egui_state
            .handle_platform_output(&gfx.window, output.platform_output.clone());
        // What the panel asked for.
        if let Some(source) = self.model.actions.open.take() {
            self.open(source);
        }
        let Some(gfx) = self.gfx.as_mut() else {
            return;
        };
        let (vw, vh) = self.model.view_px;
        if (vw, vh) != tex_size && vw > 0 && vh > 0 && self.options.frames.is_none() {
            match gfx.renderer.resize(vw, vh) {
                Ok(()) => gfx.egui_renderer.update_egui_texture_from_wgpu_texture(
                    &gfx.device,
                    &gfx.renderer.color().create_view(&Default::default()),
                    wgpu::FilterMode::Nearest,
                    gfx.view_texture,
                ),
                Err(e) => self.model.say(format!("view size: {e}")),
            }
        }
        let frame = match gfx.surface.get_current_texture() {
            wgpu::CurrentSurfaceTexture::Success(t)
            | wgpu::CurrentSurfaceTexture::Suboptimal(t) => t,
            wgpu::CurrentSurfaceTexture::Outdated | wgpu::CurrentSurfaceTexture::Lost => {
                gfx.surface.configure(&gfx.device, &gfx.config);
                return;
            }
            _ => return,
        };
        let target = frame.texture.create_view(&Default::default());
        let mut enc = gfx.device.create_command_encoder(&Default::default());
        // The 3D view.
        gfx.renderer.set_camera(self.model.state.camera.camera());
        let shown = self.shown(tex_size.0);
        let Some(gfx) = self.gfx.as_mut() else {
            return;
        };
        let free = gfx.timestamps.as_ref().and_then(|ts| {
            ts.readback
                .iter()
                .position(|(_, _, pending, _)| !pending)
                .map(|i| (&ts.set, i))
        });
        let drawn = match (gfx.lamps.as_mut(), self.model.lamps.as_mut()) {
            (Some(lamps), Some(panel)) => {
                let state = &self.model.state;
                // Sixty swing frames a second, as the one-light scenes turn their light.
                let swing = state.animate.then_some((state.time * 60.0) as u32);
                let times = lamps
                    .set_budget_ms(panel.budget_ms)
                    .and_then(|()| {
                        lamps.encode(
                            &gfx.renderer,
                            &mut enc,
                            state.mode,
                            swing,
                            free.map(|f| f.0),
                        )
                    })
                    .map_err(|e| e.to_string());
                panel.update(lamps);
                times
            }
            _ => shown.and_then(|shown| {
                gfx.renderer
                    .encode_frame(&mut enc, &shown.frame(), free.map(|f| f.0))
                    .map_err(|e| e.to_string())
            }),
        };
        let stamped = match drawn {
            Ok(times) => {
                self.model.stats.passes = times;
                self.model.stats.log.push((times, None));
                free.map(|f| f.1)
            }
            Err(e) => {
                // This frame's encoder holds a partial frame: start the window's pass afresh.
                enc = gfx.device.create_command_encoder(&Default::default());
                self.model.say(e);
                None
            }
        };
        if let (Some(i), Some(ts)) = (stamped, gfx.timestamps.as_ref()) {
            enc.resolve_query_set(&ts.set, 0..TIMESTAMPS, &ts.resolve, 0);
            enc.copy_buffer_to_buffer(&ts.resolve, 0, &ts.readback[i].0, 0, None);
        }
        // The panel, into the window and, for a screenshot, into a texture read back later.
        let ppp = output.pixels_per_point;
        for (id, deltas) in &output.textures_delta.set {
            for delta in deltas {
                gfx.egui_renderer
                    .update_texture(&gfx.device, &gfx.queue, *id, delta);
            }
        }
        let jobs = gfx.egui.tessellate(output.shapes, ppp);
        let screen = egui_wgpu::ScreenDescriptor {
            size_in_pixels: [gfx.config.width, gfx.config.height],
            pixels_per_point: ppp,
        };
        let extra =
            gfx.egui_renderer
                .update_buffers(&gfx.device, &gfx.queue, &mut enc, &jobs, &screen);
        self.frames_drawn += 1;
        let cli_last = self
            .options
            .frames
            .is_some_and(|n| self.frames_drawn == n.max(1));
        let shoot = (self.model.actions.screenshot && self.screenshot.is_none())
            || (cli_last && self.options.screenshot.is_some());
        self.model.actions.screenshot = false;
        let shot_texture = shoot.then(|| {
            gfx.device.create_texture(&wgpu::TextureDescriptor {
                label: Some("screenshot"),
                size: wgpu::Extent3d {
                    width: gfx.config.width,
                    height: gfx.config.height,
                    depth_or_array_layers: 1,
                },
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format: gfx.config.format,
                usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
                view_formats: &[],
            })
        });
        let shot_view = shot_texture
            .as_ref()
            .map(|t| t.create_view(&Default::default()));
        for view in std::iter::once(&target).chain(shot_view.as_ref()) {
            let pass = enc.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("egui"),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view,
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations {
                        load: wgpu::LoadOp::Clear(wgpu::Color::BLACK),
                        store: wgpu::StoreOp::Store,
                    },
                })],
                depth_stencil_attachment: None,
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            gfx.egui_renderer
                .render(&mut pass.forget_lifetime(), &jobs, &screen);
        }
        let shot = shot_texture.map(|t| {
            let (w, h) = (gfx.config.width, gfx.config.height);
            let row = (w * 4).div_ceil(256) * 256;
            let buffer = gfx.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("screenshot readback"),
                size: (row * h) as u64,
                usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            });
            enc.copy_texture_to_buffer(
                t.as_image_copy(),
                wgpu::TexelCopyBufferInfo {
                    buffer: &buffer,
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
            Screenshot {
                buffer,
                ready: Arc::new(AtomicBool::new(false)),
                size: (w, h),
                row,
                bgra: gfx.config.format == wgpu::TextureFormat::Bgra8Unorm,
                path: self
                    .options
                    .screenshot
                    .clone()
                    .filter(|_| cli_last)
                    .unwrap_or_else(|| PathBuf::from(format!("viewer-{}.png", self.frames_drawn))),
            }
        });
        gfx.queue
            .submit(extra.into_iter().chain(std::iter::once(enc.finish())));
        if let Some(lamps) = gfx.lamps.as_mut() {
            lamps.submitted();
        }
        for id in &output.textures_delta.free {
            gfx.egui_renderer.free_texture(id);
        }
        if let (Some(i), Some(ts)) = (stamped, gfx.timestamps.as_mut()) {
            let compared = self.model.stats.passes.compare > 0.0;
            let (buffer, ready, pending, was_compared) = &mut ts.readback[i];
            *pending = true;
            *was_compared = compared;
            let ready = ready.clone();
            buffer.map_async(wgpu::MapMode::Read, .., move |r| {
                ready.store(r.is_ok(), Ordering::Release);
            });
        }
        if let Some(shot) = shot {
            let ready = shot.ready.clone();
            shot.buffer.map_async(wgpu::MapMode::Read, .., move |r| {
                ready.store(r.is_ok(), Ordering::Release);
            });
            self.screenshot = Some(shot);
        }
        gfx.window.pre_present_notify();
        gfx.queue.present(frame);
        if cli_last && self.options.screenshot.is_none() {
            self.finish(event_loop);
        }
    }
}

/// Writes a mapped screenshot buffer as PNG.
fn write_screenshot(shot: &Screenshot) -> Result<(), String> {
    let (w, h) = shot.size;
    let mut pixels = Vec::with_capacity((w * h * 4) as usize);
    {
        let view = shot
            .buffer
            .slice(..)
            .get_mapped_range()
            .map_err(|e| format!("screenshot: {e}"))?;
        for y in 0..h {
            let start = (y * shot.row) as usize;
            for px in view[start..start + (w * 4) as usize].chunks_exact(4) {
                if shot.bgra {
                    pixels.extend_from_slice(&[px[2], px[1], px[0], 255]);
                } else {
                    pixels.extend_from_slice(&[px[0], px[1], px[2], 255]);
                }
            }
        }
    }
    shot.buffer.unmap();
    let image = image::RgbaImage::from_raw(w, h, pixels)
        .ok_or_else(|| "screenshot: wrong size".to_string())?;
    image
        .save(&shot.path)
        .map_err(|e| format!("cannot write {}: {e}", shot.path.display()))
}

fn median(mut v: Vec<f64>) -> f64 {
    if v.is_empty() {
        return f64::NAN;
    }
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

/// The command-line summary: frame rate and per-pass medians over the frames after the first
/// (which builds the pipelines).
pub fn summary(stats: &Stats, state: &ViewState) -> String {
    let frames: Vec<f64> = stats.frame_ms.iter().skip(2).map(|&t| t as f64).collect();
    let ms = median(frames);
    let mut s = format!(
        "{} {} at {}: frame {:.1} ms median ({:.1} fps)\n",
        state.shadow.technique,
        state.shadow.variant,
        state.shadow.resolution,
        ms,
        1e3 / ms
    );
    s.push_str(&pass_summary(stats));
    s
}

/// The per-pass medians of [`summary`] over the frames after the first: the CPU's recording and,
/// where the adapter writes timestamps, the GPU's.
pub fn pass_summary(stats: &Stats) -> String {
    let log = &stats.log[stats.log.len().min(1)..];
    let cpu = |f: fn(&PassTimes) -> f64| median(log.iter().map(|(p, _)| f(p)).collect());
    let gpu = |k: usize| median(log.iter().filter_map(|(_, g)| g.map(|g| g[k])).collect());
    let mut s = format!(
        "  CPU recording, ms: gbuffer {:.3}, technique {:.3}, compared {:.3}, shading {:.3}\n",
        cpu(|p| p.gbuffer),
        cpu(|p| p.technique),
        cpu(|p| p.compare),
        cpu(|p| p.shade)
    );
    if log.iter().any(|(_, g)| g.is_some()) {
        s.push_str(&format!(
            "  GPU timestamps, ms: gbuffer {:.3}, technique {:.3}, compared {:.3}, shading {:.3}\n",
            gpu(0),
            gpu(1),
            gpu(2),
            gpu(3)
        ));
    } else {
        s.push_str("  GPU timestamps: not offered by this adapter\n");
    }
    s
}
