//! Frame statistics, an ECS resource reset at the start of every frame.

use bevy_ecs::prelude::*;
use std::collections::BTreeMap;

/// What one technique's systems did in a frame.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TechniqueStats {
    /// Lights it served.
    pub lights: usize,
    /// Maps it generated.
    pub maps_generated: usize,
    /// Maps it reused from the cache.
    pub maps_reused: usize,
    /// Views it generated: each generated light's maps hold one per view (its frustum, cube
    /// faces or cascades).
    pub views_generated: usize,
    /// Receivers it evaluated.
    pub receivers_evaluated: usize,
    /// Wall time of its system, milliseconds.
    pub ms: f64,
}

/// What one light cost in a frame: its technique, what it did, its measured time, and what
/// `Auto` predicted and allowed where it chose.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub struct LightStats {
    /// The light entity.
    pub light: Entity,
    /// Its technique's name and variant, `name variant`.
    pub technique: String,
    /// Map side.
    pub resolution: u32,
    /// Views it generated (0: its maps were reused, or, [`LightStats::waited`], they wait
    /// with none made yet).
    pub views_generated: usize,
    /// Receivers it evaluated.
    pub receivers_evaluated: usize,
    /// Measured milliseconds: its generation (when it generated) and its evaluation.
    pub ms: f64,
    /// Of [`LightStats::ms`], its generation (0 where its maps were reused): from planning its
    /// views to its maps made.
    pub generate_ms: f64,
    /// Of [`LightStats::ms`], its evaluation.
    pub evaluate_ms: f64,
    /// The profile's own predictions of its generation and evaluation (before calibration and
    /// margin), for an automatic or shared choice ([`crate::Calibration`] compares them).
    pub profile_ms: Option<[f64; 2]>,
    /// What `Auto` predicted for a frame that generates (generation + evaluation, before the
    /// configuration's margin), for an automatic or shared choice; for a light that keeps its
    /// maps at the price of its evaluation ([`crate::LightShare::kept`]), its evaluation.
    pub predicted_ms: Option<f64>,
    /// The budget that prediction times its margin had to fit (the light's own, or its part of
    /// the [`crate::FrameBudget`]).
    pub budget_ms: Option<f64>,
    /// Its maps were to be made and waited for the next frame, where this frame, running over
    /// its predictions, would have passed the [`crate::FrameBudget`] with them
    /// ([`crate::deadline`]): it evaluated its old maps, or, with none, had no shadow.
    pub waited: bool,
}

/// The wall time of the pipeline's core sets in a frame, milliseconds: what the frame costs
/// beyond its techniques' systems.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct CoreStats {
    /// Caster tracking and the receivers' check ([`crate::CoreSet::Track`]).
    pub track_ms: f64,
    /// Resolving choices, keeping budgets and sharing the frame budget
    /// ([`crate::CoreSet::Resolve`]).
    pub resolve_ms: f64,
    /// Staleness ([`crate::CoreSet::Stale`]).
    pub stale_ms: f64,
}

impl CoreStats {
    /// The three sets together.
    pub fn total_ms(&self) -> f64 {
        self.track_ms + self.resolve_ms + self.stale_ms
    }
}

/// What the last frame did.
#[derive(Resource, Clone, Debug, Default, PartialEq)]
pub struct FrameStats {
    /// Frame number, from 1.
    pub frame: u64,
    /// Maps generated (all techniques).
    pub maps_generated: usize,
    /// Maps reused from the cache.
    pub maps_reused: usize,
    /// Views generated (all techniques): a generated light's frustum, cube faces or cascades.
    pub views_generated: usize,
    /// Receivers evaluated (summed over lights; a receiver outside a light's influence is not).
    pub receivers_evaluated: usize,
    /// Per technique name; a technique whose systems did not run is absent.
    pub techniques: BTreeMap<String, TechniqueStats>,
    /// Wall time per technique system, milliseconds.
    pub system_ms: BTreeMap<String, f64>,
    /// Wall time of the core sets.
    pub core: CoreStats,
    /// Every light that ran a technique this frame, in the order they ran.
    pub lights: Vec<LightStats>,
    /// The [`crate::FrameBudget`] the shared lights split, milliseconds, when the world holds one.
    pub budget_ms: Option<f64>,
}

impl FrameStats {
    /// Adds one light's work to its technique's entry (`technique`, the technique's name) and
    /// the totals, and keeps its line.
    pub fn record(&mut self, technique: &str, light: LightStats) {
        let t = self.techniques.entry(technique.to_string()).or_default();
        t.lights += 1;
        if light.views_generated > 0 {
            t.maps_generated += 1;
            self.maps_generated += 1;
            t.views_generated += light.views_generated;
            self.views_generated += light.views_generated;
        } else {
            t.maps_reused += 1;
            self.maps_reused += 1;
        }
        t.receivers_evaluated += light.receivers_evaluated;
        self.receivers_evaluated += light.receivers_evaluated;
        self.lights.push(light);
    }

    /// Keeps the line of a light whose maps wait a frame with none made yet
    /// ([`LightStats::waited`]): it neither made nor reused maps.
    pub(crate) fn record_waiting(&mut self, technique: &str, light: LightStats) {
        self.techniques
            .entry(technique.to_string())
            .or_default()
            .lights += 1;
        self.lights.push(light);
    }

    /// The measured milliseconds of every light this frame (generation and evaluation).
    pub fn lights_ms(&self) -> f64 {
        self.lights.iter().map(|l| l.ms).sum()
    }

    /// What `Auto` predicted for the lights it chose, summed (before their margins): their
    /// time in a frame where all of them generate.
    pub fn predicted_ms(&self) -> f64 {
        self.lights.iter().filter_map(|l| l.predicted_ms).sum()
    }

    /// One line for logs: `frame 3: 1 generated, 4 reused, 52133 receivers; pcf 0.41 ms, ...;
    /// core 0.80 ms`.
    pub fn summary(&self) -> String {
        let systems: Vec<String> = self
            .system_ms
            .iter()
            .map(|(k, v)| format!("{k} {v:.2} ms"))
            .collect();
        format!(
            "frame {}: {} generated, {} reused, {} receivers; {}; core {:.2} ms",
            self.frame,
            self.maps_generated,
            self.maps_reused,
            self.receivers_evaluated,
            systems.join(", "),
            self.core.total_ms()
        )
    }
}
