//! What each configuration costs against the hard shadow map, in the same run: generation at
//! the largest map resolution measured (2048² in a full run) and evaluation per million
//! receivers, as ratios to the hard map's on the same scene and backend, with the measured cause
//! of every generation above [`GENERATION_LIMIT`]. The report times the hard map just before
//! each configuration at that resolution ([`super::measure::measure`]), and a ratio
//! uses those times where the run has them ([`super::json::Run::hard_generate_ms`]), else the
//! hard map's own run on the scene.

use super::json::Report;
use crate::metrics::median;
use std::collections::BTreeMap;
use std::fmt::Write;

/// Generation within this many times the hard shadow map's is the goal; above it the table
/// names the cause.
pub const GENERATION_LIMIT: f64 = 4.0;

/// The name of the technique every ratio is to.
pub const HARD: &str = "hard-shadow-map";

/// The goal for evaluation by one lookup (shadow-width; penumbra-limit, one lookup plus its
/// lower-limit taps) against the hard map's.
pub const EVALUATION_LIMIT: f64 = 2.0;

/// The hard map's generation within this many times [`write_once_ms`] is the goal; above it
/// the section names [`HARD_OVER_WRITE_CAUSE`].
pub const HARD_OVER_WRITE_LIMIT: f64 = 3.0;

/// Where the hard map's CPU time goes beyond writing its texels once (`perf` over the `torus`
/// hard-map bench at 2048² on 2 cores, in the closing note of the stop that added this line),
/// and its ratio from cold caches (the benches' `cpu-cold` and `write-once/cold`).
pub const HARD_OVER_WRITE_CAUSE: &str = "beside the one write of every texel (25% of its \
     CPU samples on `torus` at 2048², band by band while the band is in cache), it rasterizes \
     the casters: 0.78 M depth fragments in 54,000 row spans (2x overdraw on the 9% of the map \
     the torus covers), about a third of its samples in the walk down each triangle's rows, \
     each span's depth plane and the depth test; linearizing the reached texels takes about 5%, \
     triangle setup and binning about 6%, rayon's hand-offs between the two threads about 5%. \
     The floor is a map the 32 MiB cache still holds from the write before, 5-7x faster than a \
     write that reaches memory: from cold caches, as a frame meets a map it regenerates, the \
     hard map read 1.9x, 2.5x and 3.4x writing its texels once (criterion's \
     `generate/torus/hard-shadow-map-nearest/cpu-cold/2048` beside `write-once/cold/2048`, \
     three pairs)";

/// One configuration's cost at the table's resolution, medians over the scenes it ran on.
#[derive(Clone, Debug, PartialEq)]
pub struct CostRow {
    /// `technique variant`.
    pub configuration: String,
    /// `cpu` or `gpu`.
    pub backend: String,
    /// Median generation milliseconds.
    pub generate_ms: f64,
    /// Median over scenes of generation time over the hard map's on the same scene.
    pub generate_ratio: f64,
    /// Median evaluation milliseconds per million receivers.
    pub evaluate_ms_per_m: f64,
    /// Median over scenes of evaluation time over the hard map's on the same scene.
    pub evaluate_ratio: f64,
    /// Scenes measured.
    pub scenes: usize,
}

/// Writes `value` to every texel of `map` on every thread: the floor under a map's generation
/// that [`write_once_ms`] times (and the `write-once` bench).
pub fn write_texels(map: &mut [f32], value: f32) {
    use rayon::prelude::*;
    map.par_chunks_mut(1 << 14).for_each(|c| c.fill(value));
}

/// Median milliseconds of 7 [`write_texels`] of a `resolution²` `f32` map into storage already faulted
/// in: what writing a map's texels once costs on this machine; 0 (not measured) when the map
/// cannot be allocated.
pub fn write_once_ms(resolution: u32) -> f64 {
    let n = resolution as usize * resolution as usize;
    let mut map = Vec::new();
    if n == 0 || map.try_reserve_exact(n).is_err() {
        return 0.0;
    }
    map.resize(n, 0.0f32);
    let times: Vec<f64> = (0..7)
        .map(|i| {
            let start = std::time::Instant::now();
            write_texels(&mut map, i as f32);
            start.elapsed().as_secs_f64() * 1e3
        })
        .collect();
    median(&times)
}

/// The rows at the largest resolution in `report` (and that resolution); empty without the hard
/// shadow map.
pub fn cost_rows(report: &Report) -> (u32, Vec<CostRow>) {
    let Some(resolution) = report.runs.iter().map(|r| r.resolution).max() else {
        return (0, Vec::new());
    };
    let receivers: BTreeMap<&str, usize> = report
        .references
        .iter()
        .map(|r| (r.scene.as_str(), r.receivers.max(1)))
        .collect();
    let at = |r: &&super::json::Run| r.resolution == resolution;
    let hard: BTreeMap<(&str, &str), (f64, f64)> = report
        .runs
        .iter()
        .filter(at)
        .filter(|r| r.technique == HARD)
        .map(|r| {
            let key = (r.scene.as_str(), r.backend.as_str());
            (key, (r.generate_ms.max(1e-6), r.evaluate_ms.max(1e-6)))
        })
        .collect();
    type Samples = (Vec<f64>, Vec<f64>, Vec<f64>, Vec<f64>);
    let mut per: BTreeMap<(String, String), Samples> = BTreeMap::new();
    for r in report.runs.iter().filter(at) {
        // The hard map timed beside this configuration, else its own run on the scene.
        let beside = match (r.hard_generate_ms, r.hard_evaluate_ms) {
            (Some(g), Some(e)) => Some((g.max(1e-6), e.max(1e-6))),
            _ => None,
        };
        let Some((hg, he)) =
            beside.or_else(|| hard.get(&(r.scene.as_str(), r.backend.as_str())).copied())
        else {
            continue;
        };
        let n = receivers.get(r.scene.as_str()).copied().unwrap_or(1) as f64;
        let e = per
            .entry((format!("{} {}", r.technique, r.variant), r.backend.clone()))
            .or_default();
        e.0.push(r.generate_ms);
        e.1.push(r.generate_ms / hg);
        e.2.push(r.evaluate_ms * 1e6 / n);
        e.3.push(r.evaluate_ms / he);
    }
    let rows = per
        .into_iter()
        .map(|((configuration, backend), (g, gr, e, er))| CostRow {
            configuration,
            backend,
            generate_ms: median(&g),
            generate_ratio: median(&gr),
            evaluate_ms_per_m: median(&e),
            evaluate_ratio: median(&er),
            scenes: g.len(),
        })
        .collect();
    (resolution, rows)
}

/// Why a configuration's generation costs more than [`GENERATION_LIMIT`] hard maps: the work
/// its algorithm does per map, against the hard map's one depth pass (measured on `torus` at
/// 2048² on 2 cores).
pub fn generation_cause(configuration: &str) -> &'static str {
    let mut words = configuration.split(' ');
    let technique = words.next().unwrap_or("");
    let variant = words.next().unwrap_or("");
    match (technique, variant.split('-').next().unwrap_or("")) {
        ("accumulation", _) => {
            "one depth pass per light sample: n samples cost n hard maps by definition"
        }
        ("shadow-width", "jfa") => {
            "jump flooding of the occlusion mask: log2(side) + 1 passes, 9 reads per texel each \
             (12 passes at 2048)"
        }
        ("shadow-width", "propagate") => {
            "the paper's doubling propagation: log2(side) + 1 passes over every texel, 4 or 8 \
             neighbour reads each"
        }
        ("shadow-width", _) => {
            "the occlusion mask, then the linear-time distance transform (two sweeps down the \
             columns, a lower envelope of parabolas per row); edt-back adds a second depth pass \
             for the back faces"
        }
        ("penumbra-limit", "depth") => {
            "edge tests against the 4 neighbours of every texel, then two exact nearest-seed maps \
             (near-side and far-side seeds of every depth edge: two sweeps of each column and a \
             lower envelope along each row, 16 MiB of seeds each at 2048) and the limits of every \
             texel within the widest ribbon of its seeds; on `torus` at 2048² the edges take \
             about 6-8 ms, each nearest-seed map 12, the limits 8 and the combine pass 8-10 \
             (it writes four channels per texel: 64 MiB in f32, four times the hard map's \
             bytes)"
        }
        ("penumbra-limit", _) => {
            "a ribbon of up to the widest penumbra's texels rasterized per silhouette edge, a \
             lower-limit depth pass and a combine pass over every texel (four channels: 64 MiB \
             written in f32 at 2048, four times the hard map's bytes; on `torus` at 2048² the \
             ribbons take about 5 ms, the lower limit 3 and the combine pass 9-10 of about 20); \
             where every leaf border is a silhouette edge (foliage at 2048: 12,000 ribbons about \
             200 texels wide) that is 371 M ribbon fragments, 88 per texel, against the hard \
             map's 0.64 depth fragments per texel"
        }
        ("occlusion-slices", "nbuffer") => {
            "log2(side) + 1 full-resolution levels per slice: 12 x 4 MiB per slice written at \
             2048, from a 16 MiB summed-area table per slice"
        }
        ("occlusion-slices", "mipmap") => {
            "a pyramid of exact counts per slice: a full-resolution 8-bit level 0 (4 MiB at \
             2048) and every coarser level per slice, the 16 MiB slice masks read once per group \
             of slices: the cost grows with the slice count"
        }
        ("occlusion-slices", _) => {
            "one (side + 1)² u32 summed-area table per slice (16 MiB each at 2048): the cost \
             grows with the slice count"
        }
        ("linear-light", _) => {
            "two depth passes per sample along the light (the casters, and the casters with the \
             receivers for the skins), edge finding over every texel of each, and per \
             neighbouring pair a rasterization of the skins into a full fragment map of the other \
             view and a warp over every texel of it"
        }
        _ => "",
    }
}

/// The cost section of `report.md`.
pub fn markdown(s: &mut String, report: &Report) {
    let (resolution, rows) = cost_rows(report);
    if rows.is_empty() {
        return;
    }
    let write = report.machine.write_once_ms;
    let hard_over_write = rows
        .iter()
        .find(|r| r.configuration.starts_with(&format!("{HARD} ")) && r.backend == "cpu")
        .filter(|_| write > 0.0)
        .map_or("not measured against that".to_string(), |h| {
            let ratio = h.generate_ms / write;
            let why = if ratio > HARD_OVER_WRITE_LIMIT {
                format!(" (the goal is {HARD_OVER_WRITE_LIMIT}x; {HARD_OVER_WRITE_CAUSE})")
            } else {
                String::new()
            };
            format!("{ratio:.1}x that{why}")
        });
    let _ = writeln!(
        s,
        "\n## Cost at {resolution}²\n\nGeneration at map resolution {resolution} and evaluation per million \
         receivers, medians over the scenes; `x hard`: the median over scenes of the ratio to the \
         hard shadow map on the same scene and backend, timed just before the configuration \
         in this run. Goals: generation within \
         {GENERATION_LIMIT}x (above it, the cause), single-lookup evaluation (shadow-width, \
         penumbra-limit) within {EVALUATION_LIMIT}x. Writing one `f32` map of {resolution}² once \
         takes {:.2} ms here (every thread, the map still cached from the write before); the \
         hard map's generation is {}.\n\n\
         | configuration | backend | generate ms | x hard | evaluate ms / M receivers | x hard | \
         scenes | why above {GENERATION_LIMIT}x |\n|---|---|---:|---:|---:|---:|---:|---|",
        write, hard_over_write
    );
    for r in rows {
        let why = if r.generate_ratio > GENERATION_LIMIT {
            generation_cause(&r.configuration)
        } else {
            ""
        };
        let _ = writeln!(
            s,
            "| {} | {} | {:.2} | {:.2} | {:.2} | {:.2} | {} | {why} |",
            r.configuration,
            r.backend,
            r.generate_ms,
            r.generate_ratio,
            r.evaluate_ms_per_m,
            r.evaluate_ratio,
            r.scenes
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::report::json::{ReferenceInfo, Run};

    fn run(scene: &str, technique: &str, resolution: u32, gen_ms: f64, eval_ms: f64) -> Run {
        Run {
            scene: scene.into(),
            technique: technique.into(),
            variant: "v".into(),
            backend: "cpu".into(),
            resolution,
            generate_ms: gen_ms,
            evaluate_ms: eval_ms,
            ..Default::default()
        }
    }

    #[test]
    fn ratios_are_per_scene_at_the_largest_resolution() {
        let reference = |scene: &str, receivers| ReferenceInfo {
            scene: scene.into(),
            receivers,
            ..Default::default()
        };
        let report = Report {
            references: vec![reference("a", 1000), reference("b", 4000)],
            runs: vec![
                run("a", "hard-shadow-map", 2048, 10.0, 1.0),
                run("b", "hard-shadow-map", 2048, 20.0, 2.0),
                run("a", "x", 2048, 50.0, 1.0),
                run("b", "x", 2048, 60.0, 8.0),
                // Another resolution does not count.
                run("a", "x", 256, 1.0, 1.0),
            ],
            ..Default::default()
        };
        let (resolution, rows) = cost_rows(&report);
        assert_eq!(resolution, 2048);
        let x = rows.iter().find(|r| r.configuration == "x v").unwrap();
        // Per scene: 5x and 3x generation, 1x and 4x evaluation; medians of two are means.
        assert_eq!(
            (x.generate_ratio, x.evaluate_ratio, x.scenes),
            (4.0, 2.5, 2)
        );
        // 1 ms over 1000 receivers and 8 ms over 4000: 1000 and 2000 ms per million.
        assert_eq!(x.evaluate_ms_per_m, 1500.0);
        let hard = rows
            .iter()
            .find(|r| r.configuration == "hard-shadow-map v")
            .unwrap();
        assert_eq!(hard.generate_ratio, 1.0);
        let mut md = String::new();
        markdown(&mut md, &report);
        assert!(md.contains("## Cost at 2048²"));
        assert!(md.contains("| x v | cpu | 55.00 | 4.00 | 1500.00 | 2.50 | 2 |  |"));
    }

    /// The hard map's multiple of writing its texels once is printed with the goal and its
    /// cause only above [`HARD_OVER_WRITE_LIMIT`].
    #[test]
    fn the_hard_map_over_write_once_names_its_cause_above_the_goal() {
        let section = |write_once_ms: f64| {
            let mut report = Report {
                runs: vec![run("a", HARD, 2048, 6.0, 1.0)],
                ..Default::default()
            };
            report.machine.write_once_ms = write_once_ms;
            let mut md = String::new();
            markdown(&mut md, &report);
            md
        };
        let over = section(1.0);
        assert!(over.contains("the hard map's generation is 6.0x that (the goal is 3x; beside "));
        assert!(over.contains(HARD_OVER_WRITE_CAUSE));
        let within = section(2.5);
        assert!(
            within.contains("the hard map's generation is 2.4x that.\n"),
            "{within}"
        );
        assert!(!within.contains(HARD_OVER_WRITE_CAUSE));
        assert!(section(0.0).contains("is not measured against that."));
    }

    /// Where a run carries the hard map's times from beside it, its ratios are to those, not
    /// to the hard map's own run on the scene (timed at another moment).
    #[test]
    fn ratios_are_to_the_hard_map_timed_beside() {
        let beside = |scene: &str, gen_ms, eval_ms, hard: (f64, f64)| Run {
            hard_generate_ms: Some(hard.0),
            hard_evaluate_ms: Some(hard.1),
            ..run(scene, "x", 2048, gen_ms, eval_ms)
        };
        let report = Report {
            runs: vec![
                run("a", HARD, 2048, 10.0, 1.0),
                run("b", HARD, 2048, 20.0, 2.0),
                // Timed beside a hard map of 25 ms and 2 ms on `a`; `b` has no such times.
                beside("a", 50.0, 4.0, (25.0, 2.0)),
                run("b", "x", 2048, 60.0, 8.0),
            ],
            ..Default::default()
        };
        let (_, rows) = cost_rows(&report);
        let x = rows.iter().find(|r| r.configuration == "x v").unwrap();
        // `a`: 2x and 2x beside its hard map (5x and 4x against the hard map's own run);
        // `b`: 3x and 4x against its own run. Medians of two are means.
        assert_eq!((x.generate_ratio, x.evaluate_ratio), (2.5, 3.0));
    }

    #[test]
    fn every_technique_of_the_report_has_a_cause() {
        for t in crate::report::options::all_techniques(false) {
            if t.name() == "hard-shadow-map" || t.name() == "pcf" || t.name() == "pcss" {
                continue;
            }
            let key = format!("{} {}", t.name(), t.variant());
            assert!(!generation_cause(&key).is_empty(), "{key}");
        }
    }
}
