//! A [`TechniqueProfile`] from a `report.json` of this machine, for the frame pipeline's `Auto`
//! choice: per technique, variant, backend, resolution and light kind (the kind of each built-in
//! scene's light), the median time (generation + evaluation) and the mean image error (`image_rms_255`; `rms_255`
//! in a report that predates it).

use crate::scenes::catalogue::build;
use shadow_frame::{ProfileEntry, TechniqueProfile};
use soft_shadow_core::{Backend, LightKind, Result, ShadowError};
use std::collections::BTreeMap;

type Key = (String, String, &'static str, u32, LightKind);

/// Parses `report.json` text; runs on scenes that are not built in are skipped.
pub fn from_report_json(text: &str) -> Result<TechniqueProfile> {
    let bad = |m: String| ShadowError::InvalidScene(format!("report.json: {m}"));
    let json: serde_json::Value = serde_json::from_str(text).map_err(|e| bad(e.to_string()))?;
    let runs = json["runs"]
        .as_array()
        .ok_or_else(|| bad("no `runs` array".into()))?;
    let mut kinds: BTreeMap<String, Option<LightKind>> = BTreeMap::new();
    let mut groups: BTreeMap<Key, (Vec<f64>, Vec<f64>)> = BTreeMap::new();
    for r in runs {
        let field = |k: &str| r[k].as_str().map(str::to_string);
        let num = |k: &str| r[k].as_f64();
        let (Some(scene), Some(t), Some(v), Some(b)) = (
            field("scene"),
            field("technique"),
            field("variant"),
            field("backend"),
        ) else {
            return Err(bad(format!(
                "a run lacks scene/technique/variant/backend: {r}"
            )));
        };
        let (Some(g), Some(e), Some(rms), Some(res)) = (
            num("generate_ms"),
            num("evaluate_ms"),
            num("image_rms_255").or_else(|| num("rms_255")),
            num("resolution"),
        ) else {
            return Err(bad(format!("a run lacks its numbers: {r}")));
        };
        let kind = *kinds
            .entry(scene.clone())
            .or_insert_with(|| build(&scene).ok().map(|s| s.light.kind()));
        let Some(kind) = kind else { continue };
        let backend = if b == "gpu" { "gpu" } else { "cpu" };
        let entry = groups.entry((t, v, backend, res as u32, kind)).or_default();
        entry.0.push(g + e);
        entry.1.push(rms);
    }
    let entries = groups
        .into_iter()
        .map(
            |((technique, variant, backend, resolution, light), (times, rms))| ProfileEntry {
                technique,
                variant,
                light,
                backend: if backend == "gpu" {
                    Backend::Gpu
                } else {
                    Backend::Cpu
                },
                resolution,
                time_ms: crate::metrics::median(&times),
                rms_255: rms.iter().sum::<f64>() / rms.len() as f64,
            },
        )
        .collect();
    Ok(TechniqueProfile { entries })
}
