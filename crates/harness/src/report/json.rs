//! `report.json`: field names are a stable contract (`docs/report.md`).

use crate::metrics::Errors;
use serde::{Deserialize, Serialize};

/// The whole report.
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
pub struct Report {
    /// Format version (1).
    pub version: u32,
    /// Where it ran.
    pub machine: Machine,
    /// One entry per scene's reference.
    pub references: Vec<ReferenceInfo>,
    /// One entry per technique x variant x backend x resolution x scene.
    pub runs: Vec<Run>,
    /// What each column of each scene's PNG strip shows.
    #[serde(default)]
    pub strips: Vec<Strip>,
    /// Configurations that did not run, each with the reason (a light kind the technique does
    /// not model, a resolution above the backend's limit, a memory need over the budget).
    #[serde(default)]
    pub skipped: Vec<String>,
    /// Every technique over the frames a person looks at ([`super::seen`]).
    #[serde(default)]
    pub as_seen: Vec<SeenRun>,
    /// The scenes of many lamps, each walked under one frame budget ([`super::lamps`]).
    #[serde(default)]
    pub frames: Vec<crate::frames::FramesRun>,
}

/// One technique over one scene's viewing frame ([`crate::as_seen`]): the artefacts a person
/// sees there.
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
pub struct SeenRun {
    /// Scene name.
    pub scene: String,
    /// The scene's light kind (`"disk"`, `"rect"`, ...).
    pub light: String,
    /// Technique name.
    pub technique: String,
    /// Variant label.
    pub variant: String,
    /// `"cpu"` or `"gpu"`.
    pub backend: String,
    /// Map side.
    pub resolution: u32,
    /// Receivers in the frame.
    pub receivers: usize,
    /// Receivers the reference sees at least half lit drawn at less than half of it.
    pub darkened: usize,
    /// False umbra per million receivers ([`crate::as_seen::Artefacts::false_umbra`]).
    pub false_umbra_per_million: f64,
    /// Leaks per million receivers ([`crate::as_seen::Artefacts::leaks`]).
    pub leaks_per_million: f64,
    /// Leaks on the casters' own surfaces per million receivers.
    pub object_leaks_per_million: f64,
    /// Mean FLIP over the frame's receivers, the shaded frame against the reference's
    /// ([`crate::as_seen::flip`]).
    pub flip_mean: f32,
    /// 95th percentile of FLIP over the frame's receivers.
    pub flip_p95: f32,
    /// The report's image error over the frame's receivers (`image_rms_255`, 1/255), beside
    /// FLIP (0 in reports written before it was measured).
    #[serde(default)]
    pub image_rms_255: f64,
    /// Wall time of the frame's reference, milliseconds.
    pub reference_ms: f64,
}

/// The columns of one scene's PNG strip (rows: `V`; the shaded image `E0 V / E0_max`; its
/// signed error, red = too dark, blue = too bright).
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Strip {
    /// Scene name.
    pub scene: String,
    /// File name of the strip.
    pub file: String,
    /// Column labels, left to right.
    pub columns: Vec<String>,
    /// Side of one cell in pixels (the G-buffer side).
    pub size: u32,
    /// The run shown in each column after the reference, left to right.
    pub tiles: Vec<StripTile>,
}

/// The run one strip column shows.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct StripTile {
    /// Technique name.
    pub technique: String,
    /// Variant label.
    pub variant: String,
    /// `"cpu"` or `"gpu"`.
    pub backend: String,
    /// Map resolution.
    pub resolution: u32,
    /// RMS of `V * 255` against the reference.
    pub rms_255: f64,
    /// The image error (`image_rms_255` of the run).
    pub image_rms_255: f64,
}

/// The machine the report ran on.
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
pub struct Machine {
    /// CPU model.
    pub cpu: String,
    /// Worker threads.
    pub threads: usize,
    /// GPU adapter, or why there is none.
    pub gpu_adapter: String,
    /// Milliseconds to write one `f32` map of the largest resolution a run reached once on the CPU
    /// (every thread, storage already faulted in): the floor under any map's generation
    /// ([`super::cost::write_once_ms`]).
    pub write_once_ms: f64,
}

/// The reference of one scene.
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
pub struct ReferenceInfo {
    /// Scene name.
    pub scene: String,
    /// The kind of the scene's light (`"rect"`, `"linear"`, ...).
    pub light: String,
    /// For a hard case recast under another light (`acne@rect`): the scene it comes from. Only
    /// the techniques that do not model the original light run on it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub relit_from: Option<String>,
    /// `"monte-carlo"`.
    pub method: String,
    /// Samples per receiver not proven lit (more where the horizon clips the light); a receiver
    /// proven lit (no caster crosses the hull of it and the light) takes none.
    pub samples_per_pixel: u32,
    /// RMS over penumbra receivers of the standard error, times 255.
    pub std_error_255: f64,
    /// Largest per-receiver error, times 255: standard errors, and where every ray agreed the
    /// 99% bound on a missed feature (the reference's true worst error; see `ground_truth`).
    pub max_std_error_255: f64,
    /// Receivers (covered G-buffer pixels the light reaches: those every metric uses).
    pub receivers: usize,
    /// Triangles that cast shadows (what the cost model's triangle term counts).
    #[serde(default)]
    pub caster_triangles: usize,
    /// Receivers a view of the light covers (the others are evaluated at once):
    /// [`shadow_frame::SceneSize::with_views`]. Reports written before that counted those
    /// inside the map of the light's centre for every light, cube faces and cascades too.
    #[serde(default)]
    pub covered_receivers: usize,
    /// Covered G-buffer pixels no light point reaches (visibility v2: unlit, in no metric).
    pub unlit_receivers: usize,
    /// How many views the light's maps are generated for (one generation each:
    /// `soft_shadow_core::views`).
    #[serde(default = "one")]
    pub light_views: usize,
    /// How the views are chosen: `"single"`, `"cube"` (faces around a local light) or
    /// `"cascades"` (along the camera's depth, for a distant light).
    #[serde(default = "single")]
    pub view_kind: String,
    /// Receivers whose reference is in the penumbra band.
    pub penumbra_receivers: usize,
    /// Wall time of the reference.
    pub time_ms: f64,
}

fn one() -> usize {
    1
}

fn single() -> String {
    "single".into()
}

/// One measured configuration.
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
pub struct Run {
    /// Scene name.
    pub scene: String,
    /// Technique name.
    pub technique: String,
    /// Variant label.
    pub variant: String,
    /// `"cpu"` or `"gpu"`.
    pub backend: String,
    /// Map side.
    pub resolution: u32,
    /// Median generation time.
    pub generate_ms: f64,
    /// Median evaluation time.
    pub evaluate_ms: f64,
    /// The hard shadow map's median generation time on the same scene, backend and
    /// resolution, timed just before this configuration (each run after run, after its own
    /// unmeasured frame): the denominator of the cost table's generation ratio. At the cost
    /// table's resolution only (and not on the hard map's own run).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub hard_generate_ms: Option<f64>,
    /// Likewise the hard shadow map's median evaluation time.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub hard_evaluate_ms: Option<f64>,
    /// Errors against the reference.
    #[serde(flatten)]
    pub errors: Errors,
    /// Mean excess frame-to-frame change of `V` over the reference's, times 255, with the light
    /// moving by small steps (see [`super::flicker`]); on `torus` and `overlap` at the flicker
    /// resolution only.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub flicker_255: Option<f64>,
}

impl Run {
    /// Generation plus evaluation.
    pub fn total_ms(&self) -> f64 {
        self.generate_ms + self.evaluate_ms
    }

    /// `technique/variant/backend`, the label of a line in plots.
    pub fn series(&self) -> String {
        format!("{}/{}/{}", self.technique, self.variant, self.backend)
    }
}
