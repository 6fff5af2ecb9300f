//! Measured profiles for [`crate::TechniqueChoice::Auto`]: per configuration (technique, variant,
//! backend) a cost model and an error model, fitted from measurements (`harness profile` fits
//! them from a `report.json`), so `Auto` can predict what a configuration costs on a scene it
//! has never seen and how accurate it is at each map resolution.
//!
//! - **Cost**: generation `g0 + g1·t1 + g2·t2 + g3·t3` milliseconds per view over the terms
//!   of the form the technique states ([`CostForm::terms`]: triangles, a texel term, and
//!   per-triangle work that grows with the map), times the light's views
//!   ([`SceneSize::views`]); evaluation `e0 + e1·(covered receivers / 10⁶) + e2·(other
//!   receivers / 10⁶)`, the covered ones those inside the light's map ([`SceneSize::of`]).
//!   `Auto` multiplies the prediction by the entry's margin, the 95th percentile of measured
//!   over predicted time in the fit, so that its picks fit the budget.
//! - **Error**: the image error (1/255) as `a + b·log2(side)` per light kind, clamped to the
//!   resolutions it was fitted over. Maps cover what casts, so the side is the resolution
//!   relative to the casters' extent.
//!
//! The built-in profile ([`TechniqueProfile::builtin`]) was fitted from three full CPU reports
//! on a 2-core machine, each run at its median time over them; its GPU rows are CPU
//! stand-ins, which `Auto`'s reason says.

pub use crate::calibration::Calibration;
use glam::Vec3;
use soft_shadow_core::light::LightKind;
use soft_shadow_core::technique::{Backend, CostForm};
use soft_shadow_core::{Coverage, Light, LightViews, SampleView, SceneGeometry, ShadowError};

/// One configuration's fitted models.
#[derive(Clone, Debug, PartialEq)]
pub struct ProfileEntry {
    /// Technique name, as [`soft_shadow_core::TechniqueInfo::name`].
    pub technique: String,
    /// Variant label, as [`soft_shadow_core::TechniqueInfo::variant`].
    pub variant: String,
    /// Backend the configuration runs on.
    pub backend: Backend,
    /// How its generation grows with the map side.
    pub form: CostForm,
    /// Generation milliseconds: `g0 + g1·t1 + g2·t2 + g3·t3` ([`CostForm::terms`]).
    pub generate: [f64; 4],
    /// Evaluation milliseconds: `e0 + e1·(covered receivers / 10⁶) + e2·(other receivers /
    /// 10⁶)`.
    pub evaluate: [f64; 3],
    /// Per light kind, the image error `a + b·log2(side)`, in 1/255.
    pub error: Vec<(LightKind, [f64; 2])>,
    /// The smallest and largest map side the models were fitted over.
    pub sides: (u32, u32),
    /// Measured over predicted time at the 95th percentile of the fit's runs (at least 1):
    /// what `Auto` multiplies a prediction by before holding it to a budget.
    pub margin: f64,
}

/// The size of the scene a prediction is for.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SceneSize {
    /// Caster triangles.
    pub triangles: usize,
    /// Receivers evaluated per frame.
    pub receivers: usize,
    /// Of those, the receivers a view covers (the others return at once): see
    /// [`SceneSize::with_views`].
    pub covered: usize,
    /// The light's views ([`LightViews`]: one frustum, cube faces or cascades), each generated
    /// in full: generation is predicted per view and multiplied by them (0 counts as 1).
    /// The frame pipeline's `Auto` plans them as it generates them.
    pub views: usize,
}

impl SceneSize {
    /// The size of `geometry` lit by `light` with `receivers`, its views planned over
    /// `geometry` without a camera ([`LightViews::plan`]): [`SceneSize::with_views`].
    pub fn of(geometry: &SceneGeometry, light: &Light, receivers: &[Vec3]) -> Self {
        Self::with_views(
            geometry,
            light,
            receivers,
            &LightViews::plan(light, geometry, None),
        )
    }

    /// The size of `geometry` lit by `light` with `receivers` and the light's `views`: its
    /// caster triangles, its views (1 without casters), and how many receivers a view covers:
    /// with one view of the whole coverage, those inside the map the light's centre renders of
    /// what casts; with cube faces (however many), those in the direction of a face (a
    /// direction whose face holds no caster returns at once); with cascades, every one.
    pub fn with_views(
        geometry: &SceneGeometry,
        light: &Light,
        receivers: &[Vec3],
        views: &LightViews,
    ) -> Self {
        let empty = geometry.casters.is_empty();
        let covered = if empty {
            0
        } else if !views.is_single() {
            // One selection for every receiver (`LightViews::total_weight` builds it per call).
            let select = views.gpu_select(0);
            receivers.iter().filter(|p| select.total(**p) > 0.0).count()
        } else {
            let view = SampleView::center(light, &Coverage::new(geometry, light));
            let map = view.params(1);
            receivers
                .iter()
                .filter(|p| {
                    map.project(**p)
                        .is_some_and(|q| (0.0..=1.0).contains(&q.x) && (0.0..=1.0).contains(&q.y))
                })
                .count()
        };
        Self {
            triangles: geometry.casters.len(),
            receivers: receivers.len(),
            covered,
            views: if empty { 1 } else { views.len() },
        }
    }
}

impl ProfileEntry {
    /// Predicted generation + evaluation milliseconds at map side `side` for a scene of `size`:
    /// one generation per view ([`SceneSize::views`]), one evaluation.
    pub fn predict_ms(&self, size: SceneSize, side: u32) -> f64 {
        self.predict_scaled_ms(size, side, [1.0, 1.0])
    }

    /// [`ProfileEntry::predict_ms`] with its generation scaled by `generate` and its
    /// evaluation by `evaluate` (a [`Calibration`]'s factors).
    pub fn predict_scaled_ms(
        &self,
        size: SceneSize,
        side: u32,
        [generate, evaluate]: [f64; 2],
    ) -> f64 {
        let g = self.predict_generate_ms(size, side);
        let [e0, e1, e2] = self.evaluate;
        let outside = size.receivers.saturating_sub(size.covered);
        // In this order, so that factors of 1 give the sum as it always was.
        g * generate
            + e0 * evaluate
            + e1 * size.covered as f64 / 1e6 * evaluate
            + e2 * outside as f64 / 1e6 * evaluate
    }

    /// The generation part of [`ProfileEntry::predict_ms`]: milliseconds for every view.
    pub fn predict_generate_ms(&self, size: SceneSize, side: u32) -> f64 {
        let [g0, g1, g2, g3] = self.generate;
        let [t1, t2, t3] = self.form.terms(size.triangles, side);
        (g0 + g1 * t1 + g2 * t2 + g3 * t3) * size.views.max(1) as f64
    }

    /// The evaluation part of [`ProfileEntry::predict_ms`], milliseconds.
    pub fn predict_evaluate_ms(&self, size: SceneSize) -> f64 {
        let [e0, e1, e2] = self.evaluate;
        let outside = size.receivers.saturating_sub(size.covered);
        e0 + e1 * size.covered as f64 / 1e6 + e2 * outside as f64 / 1e6
    }

    /// Predicted image error (1/255) under a light of `kind` at map side `side` (clamped to
    /// [`ProfileEntry::sides`]). A kind the configuration was never measured under takes the
    /// mean of the kinds it was; `None` when it was measured under none.
    pub fn predict_error(&self, kind: LightKind, side: u32) -> Option<f64> {
        let s = (side.clamp(self.sides.0, self.sides.1).max(1) as f64).log2();
        let line = |[a, b]: [f64; 2]| (a + b * s).max(0.0);
        match self.error.iter().find(|(k, _)| *k == kind) {
            Some((_, l)) => Some(line(*l)),
            None if self.error.is_empty() => None,
            None => Some(
                self.error.iter().map(|(_, l)| line(*l)).sum::<f64>() / self.error.len() as f64,
            ),
        }
    }
}

/// `Auto`'s choice: a configuration, a map side, and what it predicts.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub struct Pick<'a> {
    /// The configuration.
    pub entry: &'a ProfileEntry,
    /// Map side.
    pub resolution: u32,
    /// Predicted generation + evaluation milliseconds (before the margin), calibrated where
    /// the pick came from [`Calibrated`].
    pub time_ms: f64,
    /// The evaluation's part of [`Pick::time_ms`], milliseconds: what a frame that keeps the
    /// pick's maps spends on it.
    pub evaluate_ms: f64,
    /// The profile's own predictions (before calibration and margin): generation (every
    /// view) and evaluation, milliseconds.
    pub profile_ms: [f64; 2],
    /// Predicted image error, 1/255.
    pub error_255: f64,
    /// The timing is a CPU row standing in for a GPU one (no GPU measurement in the profile).
    pub stand_in: bool,
}

impl Pick<'_> {
    /// The budget the pick needs: its predicted time times its configuration's margin.
    pub fn needs_ms(&self) -> f64 {
        self.time_ms * self.entry.margin.max(1.0)
    }

    /// The budget the pick needs in a frame that keeps its maps: its predicted evaluation
    /// ([`Pick::evaluate_ms`]) times its configuration's margin.
    pub fn keeps_ms(&self) -> f64 {
        self.evaluate_ms * self.entry.margin.max(1.0)
    }
}

/// A profile: every measured configuration.
#[derive(bevy_ecs::resource::Resource, Clone, Debug, Default, PartialEq)]
pub struct TechniqueProfile {
    /// The entries.
    pub entries: Vec<ProfileEntry>,
}

/// The map sides `Auto` chooses among.
pub const SIDES: [u32; 5] = [128, 256, 512, 1024, 2048];

/// The built-in profile's text ([`TechniqueProfile::to_text`]).
const BUILTIN: &str = include_str!("builtin_profile.txt");

impl TechniqueProfile {
    /// The built-in profile: fitted by `harness profile` from three runs of `harness report
    /// --backend cpu` (map sides 16 to 2048, every catalogue scene) on a 2-core CPU, each
    /// configuration's time on each scene and side the median of the three.
    pub fn builtin() -> Self {
        Self::parse(BUILTIN).unwrap_or_default()
    }

    /// The candidates for a light of `kind` on `backend`: its rows, and for a configuration with
    /// none on the GPU, its CPU row as a stand-in.
    fn candidates(&self, backend: Backend) -> impl Iterator<Item = (&ProfileEntry, bool)> {
        self.entries.iter().filter_map(move |e| {
            if e.backend == backend {
                Some((e, false))
            } else if backend == Backend::Gpu
                && e.backend == Backend::Cpu
                && !self.entries.iter().any(|o| {
                    o.backend == Backend::Gpu
                        && o.technique == e.technique
                        && o.variant == e.variant
                })
            {
                Some((e, true))
            } else {
                None
            }
        })
    }

    /// This profile with its predictions scaled by `calibration` ([`Calibrated`]).
    pub fn calibrated<'a>(&'a self, calibration: &'a Calibration) -> Calibrated<'a> {
        Calibrated {
            profile: self,
            calibration,
        }
    }

    /// [`Calibrated::options`] without calibration.
    pub fn options(
        &self,
        kind: LightKind,
        backend: Backend,
        size: SceneSize,
        max_side: impl Fn(&str, &str) -> Option<u32>,
    ) -> Vec<Pick<'_>> {
        self.calibrated(&crate::calibration::IDENTITY)
            .options(kind, backend, size, max_side)
    }

    /// [`Calibrated::pick`] without calibration.
    pub fn pick(
        &self,
        kind: LightKind,
        backend: Backend,
        budget_ms: f64,
        size: SceneSize,
        max_side: impl Fn(&str, &str) -> Option<u32>,
    ) -> Option<Pick<'_>> {
        self.calibrated(&crate::calibration::IDENTITY)
            .pick(kind, backend, budget_ms, size, max_side)
    }

    /// [`Calibrated::frontier`] without calibration.
    pub fn frontier(
        &self,
        kind: LightKind,
        backend: Backend,
        size: SceneSize,
        max_side: impl Fn(&str, &str) -> Option<u32>,
    ) -> Vec<Pick<'_>> {
        self.calibrated(&crate::calibration::IDENTITY)
            .frontier(kind, backend, size, max_side)
    }

    /// The profile as text, one configuration a line:
    /// `technique variant backend form sides margin g0 g1 g2 g3 e0 e1 e2 kind:a:b ...`, `sides` as
    /// `min-max`.
    pub fn to_text(&self) -> String {
        let mut s = String::from(
            "# technique variant backend form sides margin g0 g1 g2 g3 e0 e1 e2 light:a:b...\n\
             # generate ms = g0 + g1 t1 + g2 t2 + g3 t3 (CostForm::terms); evaluate ms = e0 + e1 \
             covered/1e6 + e2 other receivers/1e6; image error = a + b log2(side)\n",
        );
        for e in &self.entries {
            let num = |x: f64| format!("{x:.6e}");
            let errors: Vec<String> = e
                .error
                .iter()
                .map(|(k, [a, b])| format!("{}:{}:{}", k.name(), num(*a), num(*b)))
                .collect();
            s.push_str(&format!(
                "{} {} {} {} {}-{} {:.3} {} {} {} {} {} {} {} {}\n",
                e.technique,
                e.variant,
                e.backend.name(),
                e.form.name(),
                e.sides.0,
                e.sides.1,
                e.margin,
                num(e.generate[0]),
                num(e.generate[1]),
                num(e.generate[2]),
                num(e.generate[3]),
                num(e.evaluate[0]),
                num(e.evaluate[1]),
                num(e.evaluate[2]),
                errors.join(" ")
            ));
        }
        s
    }

    /// Reads [`TechniqueProfile::to_text`]'s format; a malformed line is
    /// [`ShadowError::InvalidParameter`] naming the line and what is wrong.
    pub fn parse(text: &str) -> soft_shadow_core::Result<Self> {
        Self::parse_lines(text).map_err(ShadowError::InvalidParameter)
    }

    fn parse_lines(text: &str) -> Result<Self, String> {
        let mut entries = Vec::new();
        for (i, line) in text.lines().enumerate() {
            let line = line.trim();
            if line.is_empty() || line.starts_with('#') {
                continue;
            }
            let bad = |what: &str| format!("profile line {}: {what}: {line}", i + 1);
            let w: Vec<&str> = line.split_whitespace().collect();
            if w.len() < 13 {
                return Err(bad("fewer than 13 fields"));
            }
            let num = |s: &str| -> Result<f64, String> {
                s.parse::<f64>()
                    .ok()
                    .filter(|x| x.is_finite())
                    .ok_or_else(|| bad(&format!("{s:?} is not a finite number")))
            };
            let backend = match w[2] {
                "cpu" => Backend::Cpu,
                "gpu" => Backend::Gpu,
                b => return Err(bad(&format!("unknown backend {b:?}"))),
            };
            let form = CostForm::from_name(w[3])
                .ok_or_else(|| bad(&format!("unknown form {:?}", w[3])))?;
            let sides = w[4]
                .split_once('-')
                .and_then(|(a, b)| Some((a.parse().ok()?, b.parse().ok()?)))
                .filter(|(a, b): &(u32, u32)| *a >= 1 && a <= b)
                .ok_or_else(|| bad(&format!("sides {:?} is not min-max", w[4])))?;
            let mut error = Vec::new();
            for f in &w[13..] {
                let p: Vec<&str> = f.split(':').collect();
                let kind = LightKind::ALL
                    .into_iter()
                    .find(|k| p.first() == Some(&k.name()))
                    .ok_or_else(|| bad(&format!("unknown light kind in {f:?}")))?;
                if p.len() != 3 {
                    return Err(bad(&format!("{f:?} is not light:a:b")));
                }
                error.push((kind, [num(p[1])?, num(p[2])?]));
            }
            entries.push(ProfileEntry {
                technique: w[0].into(),
                variant: w[1].into(),
                backend,
                form,
                margin: num(w[5])?.max(1.0),
                generate: [num(w[6])?, num(w[7])?, num(w[8])?, num(w[9])?],
                evaluate: [num(w[10])?, num(w[11])?, num(w[12])?],
                error,
                sides,
            });
        }
        Ok(Self { entries })
    }
}

/// A [`TechniqueProfile`] whose predictions are scaled by what the frames measured against it
/// (a [`Calibration`]: each configuration's generation by [`Calibration::generate_for`], its
/// evaluation by [`Calibration::evaluate_for`]), for choosing.
#[derive(Clone, Copy, Debug)]
pub struct Calibrated<'a> {
    /// The profile.
    pub profile: &'a TechniqueProfile,
    /// The calibration.
    pub calibration: &'a Calibration,
}

impl<'a> Calibrated<'a> {
    /// Every configuration and map side that `max_side(technique, variant)` accepts (its
    /// largest side, `None`: not available) with a predicted image error under a light of
    /// `kind`, with its predicted time for a scene of `size` (calibrated), in the profile's
    /// order.
    pub fn options(
        &self,
        kind: LightKind,
        backend: Backend,
        size: SceneSize,
        max_side: impl Fn(&str, &str) -> Option<u32>,
    ) -> Vec<Pick<'a>> {
        let mut out = Vec::new();
        for (e, stand_in) in self.profile.candidates(backend) {
            let Some(max) = max_side(&e.technique, &e.variant) else {
                continue;
            };
            let factors = [
                self.calibration.generate_for(&e.technique, &e.variant),
                self.calibration.evaluate_for(&e.technique, &e.variant),
            ];
            for side in SIDES
                .into_iter()
                .filter(|&s| s <= max && s >= e.sides.0 && s <= e.sides.1)
            {
                let Some(error_255) = e.predict_error(kind, side) else {
                    continue;
                };
                out.push(Pick {
                    entry: e,
                    resolution: side,
                    time_ms: e.predict_scaled_ms(size, side, factors),
                    evaluate_ms: e.predict_evaluate_ms(size) * factors[1],
                    profile_ms: [
                        e.predict_generate_ms(size, side),
                        e.predict_evaluate_ms(size),
                    ],
                    error_255,
                    stand_in,
                });
            }
        }
        out
    }

    /// The configuration and map side with the lowest predicted image error under a light of
    /// `kind` whose predicted time for a scene of `size` fits `budget_ms` ([`Pick::needs_ms`]),
    /// among [`Calibrated::options`]; ties go to the faster. `None` when nothing is
    /// predicted to fit.
    pub fn pick(
        &self,
        kind: LightKind,
        backend: Backend,
        budget_ms: f64,
        size: SceneSize,
        max_side: impl Fn(&str, &str) -> Option<u32>,
    ) -> Option<Pick<'a>> {
        self.options(kind, backend, size, max_side)
            .into_iter()
            .filter(|p| p.needs_ms() <= budget_ms)
            .min_by(|a, b| {
                a.error_255
                    .total_cmp(&b.error_255)
                    .then(a.time_ms.total_cmp(&b.time_ms))
            })
    }

    /// The options whose predicted error is below that of every option that needs less budget
    /// ([`Pick::needs_ms`]), cheapest first: at any budget, [`Calibrated::pick`]'s error
    /// is that of the last one the budget affords (where two options tie in error, the pick
    /// may be the other one).
    pub fn frontier(
        &self,
        kind: LightKind,
        backend: Backend,
        size: SceneSize,
        max_side: impl Fn(&str, &str) -> Option<u32>,
    ) -> Vec<Pick<'a>> {
        let mut all = self.options(kind, backend, size, max_side);
        all.sort_by(|a, b| {
            a.needs_ms()
                .total_cmp(&b.needs_ms())
                .then(a.error_255.total_cmp(&b.error_255))
                .then(a.time_ms.total_cmp(&b.time_ms))
        });
        let mut best = f64::INFINITY;
        all.retain(|p| {
            let better = p.error_255 < best;
            best = best.min(p.error_255);
            better
        });
        all
    }
}
