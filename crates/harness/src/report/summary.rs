//! The one-screen summary that opens `report.md`: for each light kind and time budget, the best
//! configuration measured here and its margin over the best baseline within the same budget; and
//! each configuration's generation-time scaling exponent.

use super::json::Report;
use std::collections::BTreeMap;

/// Per-frame budgets of the summary (generation + evaluation), milliseconds.
pub const BUDGETS_MS: [f64; 4] = [2.0, 8.0, 32.0, 128.0];

/// The techniques that stand for what engines ship today.
pub const BASELINES: [&str; 4] = ["hard-shadow-map", "pcf", "pcss", "accumulation"];

/// One configuration averaged over the scenes of one light kind.
#[derive(Clone, Debug, PartialEq)]
pub struct Config {
    /// `technique variant backend resolution`.
    pub label: String,
    /// Technique name.
    pub technique: String,
    /// `"cpu"` or `"gpu"`.
    pub backend: String,
    /// Mean `generate_ms + evaluate_ms` over the scenes.
    pub time_ms: f64,
    /// Mean `image_rms_255` over the scenes: what the summary ranks by.
    pub image_rms_255: f64,
    /// Mean `rms_255` (of `V`) over the scenes.
    pub rms_255: f64,
    /// Mean FLIP over the "as seen" frames of the light kind's scenes at the same side and
    /// backend (`None` where no frame of the kind was measured).
    pub flip: Option<f64>,
    /// Whether that FLIP is above the hard shadow map's on the same frames: never recommended.
    pub worse_than_hard: bool,
}

/// One line of the summary.
#[derive(Clone, Debug, PartialEq)]
pub struct Line {
    /// Light kind.
    pub light: String,
    /// Budget.
    pub budget_ms: f64,
    /// The lowest-error configuration within the budget.
    pub best: Option<Config>,
    /// The lowest-error baseline within the budget.
    pub baseline: Option<Config>,
}

/// Configurations per light kind: runs grouped by technique/variant/backend/resolution and
/// averaged over the scenes of that kind (a configuration missing a scene of the kind is kept
/// with the scenes it has).
pub fn configs(report: &Report) -> BTreeMap<String, Vec<Config>> {
    let kind: BTreeMap<&str, &str> = report
        .references
        .iter()
        .filter(|r| r.relit_from.is_none())
        .map(|r| (r.scene.as_str(), r.light.as_str()))
        .collect();
    // (light, label) -> (technique, backend, time, image error, V error, runs), summed.
    type Sums = (String, String, f64, f64, f64, u32);
    let mut groups: BTreeMap<(String, String), Sums> = BTreeMap::new();
    for r in &report.runs {
        let Some(&light) = kind.get(r.scene.as_str()) else {
            continue;
        };
        let label = format!(
            "{} {} {} {}",
            r.technique, r.variant, r.backend, r.resolution
        );
        let g = groups
            .entry((light.to_string(), label))
            .or_insert_with(|| (r.technique.clone(), r.backend.clone(), 0.0, 0.0, 0.0, 0));
        g.2 += r.generate_ms + r.evaluate_ms;
        g.3 += r.errors.image_rms_255;
        g.4 += r.errors.rms_255;
        g.5 += 1;
    }
    // (light, label) -> (FLIP sum, frames); the hard map's per (light, backend, side).
    let mut flips: BTreeMap<(String, String), (f64, u32)> = BTreeMap::new();
    let mut hard: BTreeMap<(String, String, u32), (f64, u32)> = BTreeMap::new();
    for r in &report.as_seen {
        let label = format!(
            "{} {} {} {}",
            r.technique, r.variant, r.backend, r.resolution
        );
        let f = flips.entry((r.light.clone(), label)).or_default();
        f.0 += r.flip_mean as f64;
        f.1 += 1;
        if r.technique == "hard-shadow-map" {
            let h = hard
                .entry((r.light.clone(), r.backend.clone(), r.resolution))
                .or_default();
            h.0 += r.flip_mean as f64;
            h.1 += 1;
        }
    }
    let mean = |(sum, n): (f64, u32)| sum / n.max(1) as f64;
    let mut out: BTreeMap<String, Vec<Config>> = BTreeMap::new();
    for ((light, label), (technique, backend, t, image, v, n)) in groups {
        let flip = flips
            .get(&(light.clone(), label.clone()))
            .copied()
            .map(mean);
        let side: u32 = label
            .rsplit(' ')
            .next()
            .and_then(|r| r.parse().ok())
            .unwrap_or(0);
        let hard_flip = hard
            .get(&(light.clone(), backend.clone(), side))
            .copied()
            .map(mean);
        let worse_than_hard = matches!((flip, hard_flip), (Some(f), Some(h)) if f > h);
        out.entry(light).or_default().push(Config {
            label,
            technique,
            backend,
            time_ms: t / n as f64,
            image_rms_255: image / n as f64,
            rms_255: v / n as f64,
            flip,
            worse_than_hard,
        });
    }
    out
}

/// The lowest-image-error configuration of `c` within `budget`, leaving out what a person sees
/// as worse than the hard shadow map ([`Config::worse_than_hard`]).
fn best<'a>(c: impl Iterator<Item = &'a Config>, budget: f64) -> Option<Config> {
    c.filter(|c| c.time_ms <= budget && !c.worse_than_hard)
        .min_by(|a, b| {
            a.image_rms_255
                .total_cmp(&b.image_rms_255)
                .then(a.time_ms.total_cmp(&b.time_ms))
        })
        .cloned()
}

/// The summary lines, light kinds in name order, budgets ascending.
pub fn lines(report: &Report) -> Vec<Line> {
    let mut out = Vec::new();
    for (light, cs) in configs(report) {
        for budget_ms in BUDGETS_MS {
            out.push(Line {
                light: light.clone(),
                budget_ms,
                best: best(cs.iter(), budget_ms),
                baseline: best(
                    cs.iter()
                        .filter(|c| BASELINES.contains(&c.technique.as_str())),
                    budget_ms,
                ),
            });
        }
    }
    out
}

/// The "which technique" table for users, in Markdown: per light kind and budget, what to use:
/// the lowest-image-error configuration measured on `backend` whose mean time fits the budget,
/// paper technique or baseline, with the Rust expression that builds it
/// ([`soft_shadow_core::TechniqueInfo::call`]) and its mean FLIP over the light kind's "as seen"
/// frames (none whose FLIP is above the hard map's); beside it the best of the other kind within
/// the same budget (the best baseline where a paper technique wins, and by how much; the best
/// paper technique where a baseline wins). A light kind no paper technique ran on is left out.
pub fn choices(report: &Report, backend: &str, budgets: &[f64]) -> String {
    let registry = soft_shadow_techniques::registry();
    let call = |technique: &str, variant: &str| {
        registry
            .find(technique, variant)
            .map_or_else(|| "–".to_string(), |t| format!("`{}`", t.call()))
    };
    // `technique variant at side²`, and the call.
    let named = |c: &Config| {
        let mut words = c.label.split(' ');
        let (t, v) = (words.next().unwrap_or(""), words.next().unwrap_or(""));
        let res = words.nth(1).unwrap_or("");
        (format!("{t} {v} at {res}²"), call(t, v))
    };
    let is_baseline = |c: &Config| BASELINES.contains(&c.technique.as_str());
    let mut out = String::from(
        "| light | budget | use | build it with | image error | FLIP | ms | best of the other kind | image error | ms | a paper technique wins by |\n\
         |---|---:|---|---|---:|---:|---:|---|---:|---:|---:|\n",
    );
    for (light, cs) in configs(report) {
        let on: Vec<&Config> = cs.iter().filter(|c| c.backend == backend).collect();
        if !on.iter().any(|c| !is_baseline(c)) {
            continue;
        }
        for &budget in budgets {
            let technique = best(on.iter().copied().filter(|c| !is_baseline(c)), budget);
            let baseline = best(on.iter().copied().filter(|c| is_baseline(c)), budget);
            let row = match (&technique, &baseline) {
                (None, None) => "nothing fits | | | | | | | | ".to_string(),
                _ => {
                    let technique_wins = match (&technique, &baseline) {
                        (Some(t), Some(b)) => t.image_rms_255 < b.image_rms_255,
                        (t, _) => t.is_some(),
                    };
                    let (used, other) = if technique_wins {
                        (technique.as_ref(), baseline.as_ref())
                    } else {
                        (baseline.as_ref(), technique.as_ref())
                    };
                    let used = used.expect("one of them fits");
                    let (name, call) = named(used);
                    let flip = used.flip.map_or("–".to_string(), |f| format!("{f:.4}"));
                    let other_cells = match other {
                        Some(o) => {
                            format!("{} | {:.2} | {:.1}", named(o).0, o.image_rms_255, o.time_ms)
                        }
                        None => "nothing fits | | ".to_string(),
                    };
                    let margin = match (technique_wins, other) {
                        (true, Some(o)) => format!(
                            "{:.2} ({:.0}%)",
                            o.image_rms_255 - used.image_rms_255,
                            100.0 * (o.image_rms_255 - used.image_rms_255) / o.image_rms_255
                        ),
                        (true, None) => "no baseline fits".to_string(),
                        (false, _) => "–".to_string(),
                    };
                    format!(
                        "{name} | {call} | {:.2} | {flip} | {:.1} | {other_cells} | {margin}",
                        used.image_rms_255, used.time_ms
                    )
                }
            };
            out.push_str(&format!("| {light} | {budget} ms | {row} |\n"));
        }
    }
    out
}

/// [`choices`] of the `report.json` at `path`, after a line saying what it was measured on.
pub fn choices_from_file(
    path: &std::path::Path,
    backend: &str,
    budgets: &[f64],
) -> crate::error::Result<String> {
    use crate::error::HarnessError;
    let text = std::fs::read_to_string(path).map_err(|e| {
        HarnessError::Usage(format!(
            "cannot read {}: {e} (run `harness report` first)",
            path.display()
        ))
    })?;
    let report: Report = serde_json::from_str(&text).map_err(|e| {
        HarnessError::Usage(format!("{} is not a report.json: {e}", path.display()))
    })?;
    let m = &report.machine;
    let mut resolutions: Vec<u32> = report
        .runs
        .iter()
        .filter(|r| r.backend == backend)
        .map(|r| r.resolution)
        .collect();
    resolutions.sort_unstable();
    resolutions.dedup();
    let device = if backend == "gpu" {
        format!("GPU: {}", m.gpu_adapter)
    } else {
        format!("CPU: {}, {} threads", m.cpu, m.threads)
    };
    let receivers = report
        .references
        .iter()
        .map(|r| r.receivers)
        .max()
        .unwrap_or(0);
    Ok(format!(
        "Measured on the {device}; map resolutions {resolutions:?}; time = generation + \
         evaluation of up to {receivers} receivers, image error in 1/255, both the mean over \
         the catalogue scenes of each light kind.\n\n{}",
        choices(&report, backend, budgets)
    ))
}

/// Least-squares slope of `log(generate_ms)` against `log(texels)` per technique/variant/backend
/// over the resolutions 256..=2048 present (at least two), using the median time per resolution
/// over scenes. Linear cost in texels is 1.
pub fn scaling_exponents(report: &Report) -> Vec<(String, f64, usize)> {
    let mut per: BTreeMap<String, BTreeMap<u32, Vec<f64>>> = BTreeMap::new();
    for r in report
        .runs
        .iter()
        .filter(|r| (256..=2048).contains(&r.resolution))
    {
        per.entry(format!("{} {} {}", r.technique, r.variant, r.backend))
            .or_default()
            .entry(r.resolution)
            .or_default()
            .push(r.generate_ms.max(1e-6));
    }
    per.into_iter()
        .filter(|(_, m)| m.len() >= 2)
        .map(|(k, m)| {
            let pts: Vec<(f64, f64)> = m
                .into_iter()
                .map(|(res, t)| {
                    let x = ((res as f64) * (res as f64)).ln();
                    (x, crate::metrics::median(&t).ln())
                })
                .collect();
            let n = pts.len() as f64;
            let (mx, my) = (
                pts.iter().map(|p| p.0).sum::<f64>() / n,
                pts.iter().map(|p| p.1).sum::<f64>() / n,
            );
            let sxy: f64 = pts.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
            let sxx: f64 = pts.iter().map(|p| (p.0 - mx).powi(2)).sum();
            (k, sxy / sxx, pts.len())
        })
        .collect()
}

/// Exponents above this are explained in the report.
pub const SCALING_LIMIT: f64 = 1.1;

/// Why a configuration's generation time grows faster than its texel count: the causes measured
/// for each technique (`key` is `technique variant backend`, as [`scaling_exponents`] names it).
pub fn scaling_cause(key: &str) -> &'static str {
    let technique = key.split(' ').next().unwrap_or("");
    let backend = key.rsplit(' ').next().unwrap_or("");
    match (technique, backend) {
        ("occlusion-slices", "cpu") => {
            "N-Buffers keep log2(side) + 1 full-resolution levels per slice (O(n log n)), each \
             read from the slice's u32 summed-area table: 16 MiB per slice at 2048 against 1 MiB \
             at 512, outside the last-level cache"
        }
        ("occlusion-slices", _) => {
            "N-Buffers keep log2(side) full-resolution levels per slice group (O(n log n))"
        }
        ("shadow-width", _) => {
            "the width map's propagation runs log2(side) passes over every texel (O(n log n))"
        }
        (_, "gpu") => {
            "memory traffic of the passes: maps of 16 MiB per layer at 2048 outgrow the caches (on \
             lavapipe, the CPU's), where 256-512 maps fit them"
        }
        _ => {
            "maps outgrow the CPU caches (16 MiB per f32 map at 2048): every pass over them costs \
             memory traffic rather than cache reads"
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::report::json::{ReferenceInfo, Run, SeenRun};

    /// A disk-light report where penumbra-limit has the lowest image error but a person sees it
    /// as worse than the hard map (its FLIP above the hard map's at the same side), and
    /// occlusion-slices is a little less accurate but not worse by FLIP.
    fn report(pl_flip: f32) -> Report {
        let run = |technique: &str, variant: &str, image: f64| {
            let mut r = Run {
                scene: "bunny".into(),
                technique: technique.into(),
                variant: variant.into(),
                backend: "cpu".into(),
                resolution: 512,
                generate_ms: 1.0,
                evaluate_ms: 1.0,
                ..Default::default()
            };
            r.errors.image_rms_255 = image;
            r
        };
        let seen = |technique: &str, variant: &str, flip_mean: f32| SeenRun {
            scene: "bunny".into(),
            light: "disk".into(),
            technique: technique.into(),
            variant: variant.into(),
            backend: "cpu".into(),
            resolution: 512,
            flip_mean,
            ..Default::default()
        };
        Report {
            references: vec![ReferenceInfo {
                scene: "bunny".into(),
                light: "disk".into(),
                ..Default::default()
            }],
            runs: vec![
                run("hard-shadow-map", "nearest", 6.0),
                run("penumbra-limit", "silhouette-f32", 2.0),
                run("occlusion-slices", "nbuffer-8", 3.0),
            ],
            as_seen: vec![
                seen("hard-shadow-map", "nearest", 0.010),
                seen("penumbra-limit", "silhouette-f32", pl_flip),
                seen("occlusion-slices", "nbuffer-8", 0.008),
            ],
            ..Default::default()
        }
    }

    /// A configuration whose FLIP is above the hard map's is never recommended, whatever its
    /// image error; one at or below it is, with its FLIP printed beside its image error.
    #[test]
    fn a_configuration_seen_worse_than_the_hard_map_is_never_recommended() {
        let table = choices(&report(0.012), "cpu", &[16.0]);
        assert!(
            table.contains(
                "| disk | 16 ms | occlusion-slices nbuffer-8 at 512² | \
                 `OcclusionSlices::new(8, Prefilter::NBuffer)` | 3.00 | 0.0080 | 2.0 | \
                 hard-shadow-map nearest at 512² | 6.00 | 2.0 | 3.00 (50%) |"
            ),
            "{table}"
        );
        assert!(!table.contains("penumbra-limit"), "{table}");
        let table = choices(&report(0.009), "cpu", &[16.0]);
        assert!(
            table.contains(
                "| disk | 16 ms | penumbra-limit silhouette-f32 at 512² | \
                 `PenumbraLimit::new(Generator::Silhouette).with_storage(Storage::F32)` | 2.00 | \
                 0.0090 | 2.0 |"
            ),
            "{table}"
        );
    }

    /// Where a baseline is the most accurate within the budget, it is what to use, with the
    /// best paper technique beside it and no margin.
    #[test]
    fn a_baseline_that_wins_is_what_to_use() {
        let mut r = report(0.009);
        for run in &mut r.runs {
            if run.technique == "hard-shadow-map" {
                run.errors.image_rms_255 = 1.0;
            }
        }
        let table = choices(&r, "cpu", &[16.0]);
        assert!(
            table.contains(
                "| disk | 16 ms | hard-shadow-map nearest at 512² | \
                 `ShadowMapBaseline::new(Filter::Hard)` | 1.00 | 0.0100 | 2.0 | \
                 penumbra-limit silhouette-f32 at 512² | 2.00 | 2.0 | – |"
            ),
            "{table}"
        );
    }
}
