//! What the frame pipeline keeps on light entities and in the world.

use bevy_ecs::prelude::*;
use glam::Vec3;
use soft_shadow_core::light::{Light, LightKind};
use soft_shadow_core::mesh::Aabb;
use soft_shadow_core::technique::{AnyMaps, Backend, DynTechnique};
use soft_shadow_core::{Context, CpuContext, GpuContext};
use std::collections::HashMap;
use std::sync::Arc;

/// How a light's technique is chosen.
#[derive(Clone)]
#[non_exhaustive]
pub enum TechniqueChoice {
    /// This technique, with these parameters.
    Explicit(Arc<dyn DynTechnique>),
    /// The configuration and map side with the lowest predicted image error whose predicted time
    /// (generation + evaluation, for the casters and receivers within the light's range) fits
    /// `budget_ms`, from
    /// the pipeline's [`crate::TechniqueProfile`]; once frames are measured, a choice that runs
    /// over the budget for [`crate::tracking::STEP_DOWN_FRAMES`] frames steps down.
    Auto {
        /// Time budget per light and frame, milliseconds.
        budget_ms: f64,
    },
    /// As `Auto`, within this light's part of the frame's [`crate::FrameBudget`], which follows
    /// what the light adds to the image ([`crate::budget`]): a light that adds little gets a
    /// cheaper configuration or a smaller map side, one that reaches nothing the camera sees
    /// costs nothing. A light of zero size takes the hard path at
    /// [`ShadowConfig::resolution`], outside the budget.
    Shared,
}

/// Per-light settings of the frame pipeline; a light without it casts no shadows.
#[derive(Component, Clone)]
pub struct ShadowConfig {
    /// The technique.
    pub choice: TechniqueChoice,
    /// Map resolution (an `Auto` or shared choice overrides it with the profile's; a zero-size
    /// light takes it as is, or [`ZERO_SIZE_SIDE`] where it is 0).
    pub resolution: u32,
    /// Radius of the light's influence around its centre: casters and receivers beyond it are
    /// ignored. `f32::INFINITY` for none (distant lights always have none).
    pub range: f32,
    /// How bright the light is, for its part of a [`crate::FrameBudget`] (only a
    /// [`TechniqueChoice::Shared`] choice reads it): a local light's radiant intensity, a
    /// distant light's irradiance at normal incidence, in any unit the frame's lights share
    /// ([`crate::budget::irradiance_estimate`]). 1 by default.
    pub intensity: f32,
}

impl ShadowConfig {
    /// An explicit technique at `resolution`, unlimited range.
    pub fn explicit(t: Arc<dyn DynTechnique>, resolution: u32) -> Self {
        Self {
            choice: TechniqueChoice::Explicit(t),
            resolution,
            range: f32::INFINITY,
            intensity: 1.0,
        }
    }

    /// An automatic choice within `budget_ms`, unlimited range.
    pub fn auto(budget_ms: f64) -> Self {
        Self {
            choice: TechniqueChoice::Auto { budget_ms },
            resolution: 0,
            range: f32::INFINITY,
            intensity: 1.0,
        }
    }

    /// An automatic choice within the light's part of the frame's [`crate::FrameBudget`]
    /// ([`TechniqueChoice::Shared`]), intensity 1, unlimited range.
    pub fn shared() -> Self {
        Self {
            choice: TechniqueChoice::Shared,
            resolution: 0,
            range: f32::INFINITY,
            intensity: 1.0,
        }
    }

    /// The same with an intensity ([`ShadowConfig::intensity`]).
    pub fn with_intensity(mut self, intensity: f32) -> Self {
        self.intensity = intensity;
        self
    }

    /// Whether `light` takes a part of the frame's [`crate::FrameBudget`]: a
    /// [`TechniqueChoice::Shared`] choice on a light of non-zero size.
    pub fn shares_budget(&self, light: &Light) -> bool {
        matches!(self.choice, TechniqueChoice::Shared) && light.size() > 0.0
    }

    /// The same with an influence radius.
    pub fn with_range(mut self, range: f32) -> Self {
        self.range = range;
        self
    }
}

/// The technique a light runs with, once chosen, and why.
#[derive(Component, Clone)]
pub struct ResolvedTechnique {
    /// The technique.
    pub technique: Arc<dyn DynTechnique>,
    /// Map resolution.
    pub resolution: u32,
    /// One line saying why (explicit, zero-size light, or the profile entry and its numbers).
    pub reason: String,
    /// For an `Auto` choice: its budget and what the profile predicted (time, image error).
    pub auto: Option<AutoPrediction>,
}

/// What `Auto` predicted for its choice, and what the frames since measured.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[non_exhaustive]
pub struct AutoPrediction {
    /// The budget, milliseconds per frame (generation + evaluation).
    pub budget_ms: f64,
    /// Predicted generation + evaluation milliseconds for this scene (calibrated,
    /// [`crate::Calibration`]); for a light that keeps its maps at the price of its evaluation
    /// ([`LightShare::kept`]), what the frame spends on it: its evaluation alone.
    pub time_ms: f64,
    /// The profile's own predictions for this scene, generation (every view) and evaluation,
    /// milliseconds (before calibration and margin): what [`crate::Calibration`] compares the
    /// measured times with.
    pub profile_ms: [f64; 2],
    /// Predicted image error, 1/255.
    pub error_255: f64,
    /// The configuration's margin: the pick needs `time_ms * margin` of budget
    /// ([`crate::ProfileEntry::margin`]).
    pub margin: f64,
    /// The latest measured generation + evaluation, which replaces the prediction once known.
    pub measured_ms: Option<f64>,
    /// Consecutive measured frames over the budget.
    pub frames_over: u32,
}

/// A light's cached maps and its latest visibilities.
#[derive(Component, Default)]
pub struct LightState {
    /// Maps from the last generation (`None` before the first).
    pub maps: Option<AnyMaps>,
    /// Set when the light, its settings or a caster within its influence changed.
    pub stale: bool,
    /// `V` per frame receiver; 1 for receivers outside the light's influence.
    pub visibility: Vec<f32>,
    /// Receivers this light evaluated in the last frame.
    pub evaluated: usize,
    /// Why this light casts no shadows, when it does not (e.g. no technique fits the budget).
    pub error: Option<String>,
    /// Milliseconds of the last frame that generated this light's maps (generation and
    /// evaluation), until the budget check reads it. On a GPU frame timed by a
    /// [`crate::GpuTiming`], its device time, a frame or two later.
    pub generated_ms: Option<f64>,
    /// For a light that shares the [`crate::FrameBudget`]: its part (`None` before the first
    /// share, and for other lights).
    pub share: Option<LightShare>,
    /// Regions of casters that changed within the light's range where they could shadow
    /// nothing the camera saw ([`crate::tracking::mark_stale`]): the maps are made again when
    /// the camera brings one into play.
    pub unseen_changes: Vec<Aabb>,
}

/// A shared light's part of the [`crate::FrameBudget`], kept in its [`LightState::share`].
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[non_exhaustive]
pub struct LightShare {
    /// Its part of the frame's contribution (of all shared lights), in `[0, 1]`.
    pub contribution: f64,
    /// The budget times that part when the budget was last shared, milliseconds: what the
    /// hysteresis compares against.
    pub proportional_ms: f64,
    /// The budget its pick was made within (milliseconds; 0 for a light that contributes
    /// nothing or that the budget could not afford): see [`crate::budget`].
    pub budget_ms: f64,
    /// The image error (1/255) the share took its missing shadow to cost, what the budget
    /// weighed its first step against: measured from its `V` (on the GPU, its probe's,
    /// [`ProbedVisibility`]) while it has a shadow and the frame's receivers are those its `V`
    /// was evaluated on
    /// ([`crate::budget::missing_shadow_255`]; the last share's while the measurement stays
    /// within [`crate::budget::SHARE_HYSTERESIS`] of it), and kept while its part stays within
    /// its band and no caster within its range changed; `None` where the share took
    /// [`crate::budget::NO_SHADOW_255`].
    pub missing_255: Option<f64>,
    /// Whether the budget priced its pick at its evaluation alone, its maps kept
    /// ([`crate::profile::Pick::keeps_ms`]): a frame that must make them again shares the
    /// budget again first.
    pub kept: bool,
}

/// Receivers an estimate over the frame's receivers reads at most (every `k`-th, evenly
/// spread, [`FrameReceivers::sample_step`]): a light's contribution and its missing shadow
/// ([`crate::budget`]), and how many of its receivers its views cover
/// ([`crate::SceneSize::covered`] as the frame predicts it). The shares and the predictions need
/// proportions, not every pixel.
pub const RECEIVER_SAMPLES: usize = 4096;

/// The points the frame shades (e.g. the camera G-buffer), with unit normals.
#[derive(Resource, Default, Clone)]
pub struct FrameReceivers {
    /// World-space positions.
    pub positions: Vec<Vec3>,
    /// Unit normals.
    pub normals: Vec<Vec3>,
    /// The view of the camera that sees them (its G-buffer's: `Camera::view(width, height)`),
    /// if any. With it a distant light's shadow is a set of cascades along the camera's depth
    /// ([`soft_shadow_core::LightViews::plan`] with what the camera sees, each cascade fitted
    /// as [`FrameSettings::cascade_fit`] says), which follow the camera: those the camera
    /// moved to other texels are made again, the others kept, and all
    /// where the split depths changed ([`soft_shadow_core::AnyMaps::follow`]). Without it a
    /// distant light has one view over everything it shadows.
    pub camera: Option<soft_shadow_core::View>,
}

impl FrameReceivers {
    /// Every how many of `n` receivers an estimate over them reads: at most
    /// [`RECEIVER_SAMPLES`].
    pub fn sample_step(n: usize) -> usize {
        n.div_ceil(RECEIVER_SAMPLES).max(1)
    }

    /// The points a distant light's cascades are fitted to
    /// ([`soft_shadow_core::LightViews::plan_seen`]) among `points` (these receivers, or some of
    /// them) on `backend` with `settings`: all of them where [`FrameSettings::cascade_fit`]
    /// fits cascades to the receivers, none where it fits them to the camera frustum's slices.
    pub(crate) fn cascade_fit<'a>(
        points: &'a [Vec3],
        backend: Backend,
        settings: &FrameSettings,
    ) -> &'a [Vec3] {
        if settings
            .cascade_fit
            .to_receivers(backend, settings.evaluate_receivers)
        {
            points
        } else {
            &[]
        }
    }

    /// What the camera sees of these receivers (`None` without a camera or with none in front of
    /// it): the depth range a distant light's cascades split, in whole steps
    /// ([`soft_shadow_core::SeenDepth::quantized`]) so that a camera that moves a little keeps
    /// the cascades' split depths.
    pub fn seen(&self) -> Option<soft_shadow_core::SeenDepth> {
        self.camera
            .and_then(|c| soft_shadow_core::SeenDepth::of_points(c, &self.positions))
            .map(soft_shadow_core::SeenDepth::quantized)
    }
}

/// Why this frame's [`FrameReceivers`] cannot be shaded (`None` when they are valid), checked
/// once per frame by [`crate::tracking::check_receivers`].
#[derive(Resource, Default, Clone)]
pub struct ReceiversError(pub Option<String>);

/// Where the frame runs its techniques, and the contexts they run in.
#[derive(Resource, Clone)]
pub struct FrameBackend {
    /// CPU or GPU.
    pub backend: Backend,
    /// The context of [`Backend::Cpu`] (its pool and memory budget).
    pub cpu: Arc<CpuContext>,
    /// The context for [`Backend::Gpu`].
    pub gpu: Option<Arc<GpuContext>>,
}

impl Default for FrameBackend {
    fn default() -> Self {
        Self {
            backend: Backend::Cpu,
            cpu: Arc::new(CpuContext::new()),
            gpu: None,
        }
    }
}

impl FrameBackend {
    /// The GPU backend on `gpu`.
    pub fn gpu(gpu: Arc<GpuContext>) -> Self {
        Self {
            backend: Backend::Gpu,
            gpu: Some(gpu),
            ..Self::default()
        }
    }

    /// Gives the maps a light replaces back to the pool of the context that made them, for the
    /// next generation on this thread: GPU maps to this backend's GPU context's pool where
    /// that context made them (others are dropped, [`AnyMaps::recycle`]); CPU maps are
    /// dropped, their storage going back to the CPU pool.
    pub(crate) fn retire(&self, maps: Option<AnyMaps>) {
        if let Some(maps) = maps {
            maps.recycle(self.gpu.as_deref());
        }
    }

    /// The context a generation runs in: the CPU's, or the GPU's (an error naming the missing
    /// context when the GPU backend has none).
    pub fn context(&self) -> Result<Context<'_>, String> {
        match (self.backend, &self.gpu) {
            (Backend::Cpu, _) => Ok(Context::Cpu(&self.cpu)),
            (Backend::Gpu, Some(gpu)) => Ok(Context::Gpu(gpu)),
            (Backend::Gpu, None) => {
                Err("the GPU backend was asked for without a GPU context".to_string())
            }
        }
    }
}

/// The texels of the last visibility texture [`crate::gpu_frame::record_visibility`] recorded into: what a GPU
/// frame's lights evaluate, which `Auto` and the shared budget predict for them in place of the
/// frame's receivers when those are not evaluated ([`crate::FrameSettings::evaluate_receivers`]
/// off). `record_visibility` keeps it; insert it before the first frame (your G-buffer's width
/// times height) so that the first frame's picks predict the texels too, and its second does
/// not pick again.
#[derive(Resource, Clone, Copy, Debug, PartialEq, Eq)]
pub struct RecordedTexels(pub usize);

/// The lights' `V` at the frame's sampled receivers, as the last probe brought it: what the
/// shared budget measures a GPU light's missing shadow from
/// ([`crate::budget::missing_shadow_255`]) while the frame's receivers are those it was
/// recorded for.
#[derive(Resource, Clone, Debug, Default, PartialEq)]
pub struct ProbedVisibility {
    /// The frame's receivers it was recorded for (a hash of them).
    pub receivers: u64,
    /// Per light, `V` per frame receiver: measured at the sampled ones, NaN at the others (no
    /// measurement; [`crate::budget::missing_shadow_255`] skips them). A light that made its
    /// maps again since leaves it.
    pub lights: std::collections::HashMap<Entity, Vec<f32>>,
}

/// The layer of [`crate::gpu_frame::FrameTextures::visibility`] a light's `V` is written to: a
/// component of the light's entity. Lights without one are not recorded.
#[derive(Component, Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct VisibilityLayer(pub u32);

/// Frame settings.
#[derive(Resource, Clone, Copy)]
#[non_exhaustive]
pub struct FrameSettings {
    /// Reuse maps when nothing that affects them changed (off: every light regenerates every
    /// frame, the baseline the caching is measured against).
    pub caching: bool,
    /// Evaluate [`FrameReceivers`] into [`LightState::visibility`] (off: the maps are made and
    /// kept, `visibility` is left empty and nothing is read back, for a renderer that takes
    /// `V` from its own textures with [`crate::gpu_frame`], but the passes' timestamps and the
    /// lights' `V` at the sampled receivers where a `GpuTiming` and a `ShadowProbe` ask for them; the receivers still bound what the maps cover, and
    /// predictions count the texels `V` is recorded over, [`RecordedTexels`]).
    pub evaluate_receivers: bool,
    /// Keep the [`crate::Calibration`] from what every frame measures, and keep a CPU
    /// frame's shared budget as it runs, a light's maps waiting a frame where the frame's
    /// measured times say they would pass it ([`crate::deadline`]) (off: the calibration stays
    /// as it is, the profile as fitted unless you set it, and picks follow predictions alone:
    /// the same picks on every run).
    pub calibrating: bool,
    /// What a distant light's cascades are fitted to across the light, where
    /// [`FrameReceivers::camera`] names the camera ([`CascadeFit`]).
    pub cascade_fit: CascadeFit,
}

impl Default for FrameSettings {
    fn default() -> Self {
        Self {
            caching: true,
            evaluate_receivers: true,
            calibrating: true,
            cascade_fit: CascadeFit::Auto,
        }
    }
}

/// What a distant light's cascades are fitted to across the light
/// ([`FrameSettings::cascade_fit`]). Their depth ranges split what [`FrameReceivers`] span
/// either way.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[non_exhaustive]
pub enum CascadeFit {
    /// [`CascadeFit::Receivers`] on the CPU backend where the frame evaluates its receivers
    /// (`V` is read there and nowhere else), [`CascadeFit::Slices`] otherwise: a GPU frame
    /// may record `V` over your G-buffer's textures ([`crate::gpu_frame`]), evaluating its
    /// receivers or not, and [`FrameReceivers`] may be a few points of them.
    #[default]
    Auto,
    /// Each cascade to the frame's receivers in its depth range
    /// ([`soft_shadow_core::LightViews::plan_seen`], the sample-distribution idea): the finest
    /// texels, where [`FrameReceivers`] hold every point `V` is read at (a texel of your
    /// G-buffer outside every window reads no shadow).
    Receivers,
    /// Each cascade to its slice of the camera's frustum within the scene's bounds
    /// ([`soft_shadow_core::LightViews::plan`]): every point the camera sees.
    Slices,
}

impl CascadeFit {
    /// Whether cascades are fitted to the frame's receivers on `backend` with `evaluated`
    /// ([`FrameSettings::evaluate_receivers`]).
    pub fn to_receivers(self, backend: Backend, evaluated: bool) -> bool {
        match self {
            CascadeFit::Auto => backend == Backend::Cpu && evaluated,
            CascadeFit::Receivers => true,
            CascadeFit::Slices => false,
        }
    }
}

impl FrameSettings {
    /// With [`FrameSettings::caching`] set.
    pub fn with_caching(mut self, caching: bool) -> Self {
        self.caching = caching;
        self
    }

    /// With [`FrameSettings::cascade_fit`] set.
    pub fn with_cascade_fit(mut self, fit: CascadeFit) -> Self {
        self.cascade_fit = fit;
        self
    }

    /// With [`FrameSettings::evaluate_receivers`] set.
    pub fn with_evaluate_receivers(mut self, evaluate: bool) -> Self {
        self.evaluate_receivers = evaluate;
        self
    }

    /// With [`FrameSettings::calibrating`] set.
    pub fn with_calibrating(mut self, calibrating: bool) -> Self {
        self.calibrating = calibrating;
        self
    }
}

/// The map side of a zero-size light whose config names none (an `Auto` or shared choice:
/// zero-size lights take the hard path, which the profile does not size).
pub const ZERO_SIZE_SIDE: u32 = 1024;

/// The technique zero-size (point) lights take: a hard shadow map.
#[derive(Resource, Clone, Default)]
pub struct HardShadowPath(pub Option<Arc<dyn DynTechnique>>);

/// Last known world bounds of every caster entity, and the regions that changed this frame.
#[derive(Resource, Default)]
pub struct CasterIndex {
    /// Bounds by entity.
    pub bounds: HashMap<Entity, Aabb>,
    /// Old and new bounds of casters that moved, changed mesh, appeared or disappeared.
    pub changed: Vec<Aabb>,
}

/// The sphere a light influences: centre and radius (infinite for distant lights).
pub fn influence(light: &Light, range: f32) -> (Vec3, f32) {
    match light.center() {
        soft_shadow_core::light::LightPoint::Position(p) if light.kind() != LightKind::Distant => {
            (p, range)
        }
        _ => (Vec3::ZERO, f32::INFINITY),
    }
}

/// Whether a caster with bounds `b` can shadow anything for `light` with influence radius
/// `range`: the box reaches into the influence sphere and, for a one-sided emitter (rect, disk,
/// triangle),
/// lies at least partly in front of the emitting plane. This is the light's frustum for the
/// frame pipeline's bookkeeping.
pub fn caster_reaches(light: &Light, range: f32, b: &Aabb) -> bool {
    let (c, r) = influence(light, range);
    if !box_in_sphere(b, c, r) {
        return false;
    }
    match light.front() {
        Some((p, n)) => b.corners().iter().any(|q| (*q - p).dot(n) > 0.0),
        None => true,
    }
}

/// Whether the box `b` reaches into the sphere `(c, r)`.
pub fn box_in_sphere(b: &Aabb, c: Vec3, r: f32) -> bool {
    if !r.is_finite() {
        return true;
    }
    let q = c.clamp(b.min, b.max);
    q.distance_squared(c) <= r * r
}

/// The part of triangle `t` inside the box `b`, as triangles (a fan over the clipped polygon;
/// none when the triangle misses the box, `t` itself when it lies inside).
pub fn clip_to_box(t: &[Vec3; 3], b: &Aabb) -> Vec<[Vec3; 3]> {
    let inside = |p: &Vec3| p.cmpge(b.min).all() && p.cmple(b.max).all();
    if t.iter().all(inside) {
        return vec![*t];
    }
    let mut poly: Vec<Vec3> = t.to_vec();
    for axis in 0..3 {
        for (bound, keep_below) in [(b.max[axis], true), (b.min[axis], false)] {
            let keep = |p: &Vec3| {
                if keep_below {
                    p[axis] <= bound
                } else {
                    p[axis] >= bound
                }
            };
            let mut out = Vec::with_capacity(poly.len() + 1);
            for i in 0..poly.len() {
                let (a, c) = (poly[i], poly[(i + 1) % poly.len()]);
                if keep(&a) {
                    out.push(a);
                }
                if keep(&a) != keep(&c) {
                    let s = (bound - a[axis]) / (c[axis] - a[axis]);
                    out.push(a + (c - a) * s);
                }
            }
            poly = out;
            if poly.len() < 3 {
                return Vec::new();
            }
        }
    }
    (1..poly.len() - 1)
        .map(|i| [poly[0], poly[i], poly[i + 1]])
        .collect()
}
