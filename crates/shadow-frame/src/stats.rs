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
    /// Wall time per system, milliseconds.
    pub system_ms: BTreeMap<String, f64>,
}

impl FrameStats {
    /// Adds one light's work to `technique`'s entry and the totals: the views it generated
    /// (0: its maps were reused) and the receivers it evaluated.
    pub fn record(&mut self, technique: &str, views_generated: usize, evaluated: usize) {
        let t = self.techniques.entry(technique.to_string()).or_default();
        t.lights += 1;
        if views_generated > 0 {
            t.maps_generated += 1;
            self.maps_generated += 1;
            t.views_generated += views_generated;
            self.views_generated += views_generated;
        } else {
            t.maps_reused += 1;
            self.maps_reused += 1;
        }
        t.receivers_evaluated += evaluated;
        self.receivers_evaluated += evaluated;
    }

    /// One line for logs: `frame 3: 1 generated, 4 reused, 52133 receivers; pcf 0.41 ms, ...`.
    pub fn summary(&self) -> String {
        let systems: Vec<String> = self
            .system_ms
            .iter()
            .map(|(k, v)| format!("{k} {v:.2} ms"))
            .collect();
        format!(
            "frame {}: {} generated, {} reused, {} receivers; {}",
            self.frame,
            self.maps_generated,
            self.maps_reused,
            self.receivers_evaluated,
            systems.join(", ")
        )
    }
}
