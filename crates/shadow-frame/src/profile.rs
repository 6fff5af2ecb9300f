//! Measured profiles for [`crate::TechniqueChoice::Auto`]: per light kind and backend,
//! each configuration's time (generation + evaluation) and error, from a `report.json` of this
//! machine (the harness loads it) or the built-in defaults.

use soft_shadow_core::light::LightKind;
use soft_shadow_core::technique::Backend;

/// One measured configuration.
#[derive(Clone, Debug, PartialEq)]
pub struct ProfileEntry {
    /// Technique name, as [`soft_shadow_core::TechniqueInfo::name`].
    pub technique: String,
    /// Variant label, as [`soft_shadow_core::TechniqueInfo::variant`].
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

/// One built-in default row: technique name, variant label, light kind, time (ms) and RMS of
/// `V * 255`, measured by `report --quick` on a 2-core CPU at map resolution 256 (CPU time
/// medians and mean rms over the built-in scenes of that light kind, as
/// `harness::profile::from_report_json` reads them). Each technique crate lists its own
/// (`PROFILE_DEFAULTS`) and registers them with
/// [`crate::FramePipeline::add_profile_defaults`].
pub type DefaultCost = (&'static str, &'static str, LightKind, f64, f64);

impl TechniqueProfile {
    /// Adds built-in default rows, for both backends.
    pub fn extend_defaults(&mut self, rows: &[DefaultCost]) {
        let entries = rows.iter().flat_map(|&(t, v, light, time_ms, rms_255)| {
            [Backend::Cpu, Backend::Gpu].map(|backend| ProfileEntry {
                technique: t.into(),
                variant: v.into(),
                light,
                backend,
                resolution: 256,
                time_ms,
                rms_255,
            })
        });
        self.entries.extend(entries);
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
