//! Measured profiles for [`crate::frame::TechniqueChoice::Auto`]: per light kind and backend,
//! each configuration's time (generation + evaluation) and error, from a `report.json` of this
//! machine (the harness loads it) or the built-in defaults.

use crate::light::LightKind;
use crate::technique::Backend;

/// One measured configuration.
#[derive(Clone, Debug, PartialEq)]
pub struct ProfileEntry {
    /// Technique name, as [`crate::DynTechnique::name`].
    pub technique: String,
    /// Variant label, as [`crate::DynTechnique::variant`].
    pub variant: String,
    /// Light kind the measurement is for.
    pub light: LightKind,
    /// Backend it ran on.
    pub backend: Backend,
    /// Map resolution.
    pub resolution: u32,
    /// Generation + evaluation, milliseconds (median over the profile's scenes of this kind).
    pub time_ms: f64,
    /// RMS of `V * 255` against the reference (mean over those scenes).
    pub rms_255: f64,
}

/// A profile: every measured configuration.
#[derive(bevy_ecs::resource::Resource, Clone, Debug, Default, PartialEq)]
pub struct TechniqueProfile {
    /// The entries.
    pub entries: Vec<ProfileEntry>,
}

/// Built-in defaults: `report --quick` on a 2-core CPU (visibility v2, maps fitted to casters), map
/// resolution 256, CPU time medians and mean rms over the built-in scenes of each light kind, as
/// `harness::profile::from_report_json` reads them; one row per light kind and technique family.
/// Used when no `report.json` profile is given.
const DEFAULTS: &[(&str, &str, LightKind, f64, f64)] = &[
    ("hard-shadow-map", "nearest", LightKind::Rect, 1.2, 30.9),
    ("pcf", "r2", LightKind::Rect, 1.7, 21.7),
    ("pcss", "7x7-9x9", LightKind::Rect, 2.9, 10.8),
    ("accumulation", "n16", LightKind::Rect, 16.5, 9.0),
    ("occlusion-slices", "sat-8", LightKind::Rect, 4.8, 13.6),
    ("occlusion-slices", "nbuffer-8", LightKind::Rect, 23.8, 14.3),
    ("hard-shadow-map", "nearest", LightKind::Linear, 1.1, 38.0),
    ("pcss", "7x7-9x9", LightKind::Linear, 3.1, 12.0),
    ("accumulation", "n16", LightKind::Linear, 14.8, 2.4),
    ("linear-light", "n5", LightKind::Linear, 26.5, 2.5),
    ("hard-shadow-map", "nearest", LightKind::Disk, 44.8, 22.5),
    ("pcss", "7x7-9x9", LightKind::Disk, 14.3, 18.6),
    (
        "penumbra-limit",
        "silhouette-f32",
        LightKind::Disk,
        206.9,
        20.5,
    ),
    ("accumulation", "n16", LightKind::Disk, 334.1, 16.1),
    ("hard-shadow-map", "nearest", LightKind::Sphere, 2.0, 27.6),
    ("pcss", "7x7-9x9", LightKind::Sphere, 5.7, 9.3),
    ("accumulation", "n16", LightKind::Sphere, 26.9, 5.4),
    ("occlusion-slices", "sat-16", LightKind::Sphere, 12.8, 9.3),
    ("hard-shadow-map", "nearest", LightKind::Distant, 0.8, 6.4),
    ("pcf", "r2", LightKind::Distant, 1.6, 5.3),
    (
        "penumbra-limit",
        "silhouette-f32",
        LightKind::Distant,
        3.0,
        4.4,
    ),
    ("accumulation", "n16", LightKind::Distant, 8.5, 4.5),
    ("hard-shadow-map", "nearest", LightKind::Triangle, 0.9, 17.5),
    ("pcss", "7x7-9x9", LightKind::Triangle, 2.0, 6.9),
    ("accumulation", "n16", LightKind::Triangle, 14.6, 2.8),
    ("linear-light", "n5", LightKind::Triangle, 67.1, 7.8),
    ("occlusion-slices", "sat-8", LightKind::Triangle, 7.8, 4.4),
    (
        "penumbra-limit",
        "silhouette-f32",
        LightKind::Triangle,
        3.0,
        11.6,
    ),
];

impl TechniqueProfile {
    /// The built-in defaults, for both backends.
    pub fn defaults() -> Self {
        let entries = DEFAULTS
            .iter()
            .flat_map(|&(t, v, light, time_ms, rms_255)| {
                [Backend::Cpu, Backend::Gpu].map(|backend| ProfileEntry {
                    technique: t.into(),
                    variant: v.into(),
                    light,
                    backend,
                    resolution: 256,
                    time_ms,
                    rms_255,
                })
            })
            .collect();
        Self { entries }
    }

    /// The entry with the lowest error among those for `light` on `backend` whose time fits
    /// `budget_ms` and that `available(technique, variant)` accepts (ties: the faster one, then
    /// the first); `None` when nothing fits.
    pub fn pick(
        &self,
        light: LightKind,
        backend: Backend,
        budget_ms: f64,
        available: impl Fn(&str, &str) -> bool,
    ) -> Option<&ProfileEntry> {
        self.entries
            .iter()
            .filter(|e| e.light == light && e.backend == backend && e.time_ms <= budget_ms)
            .filter(|e| available(&e.technique, &e.variant))
            .min_by(|a, b| {
                a.rms_255
                    .total_cmp(&b.rms_255)
                    .then(a.time_ms.total_cmp(&b.time_ms))
            })
    }
}
