//! A [`TechniqueProfile`] fitted from a report (`harness profile`), and how well it predicts
//! scenes it was not fitted on (the report's validation section).
//!
//! Per configuration (technique, variant, backend), from its runs over scenes and map sides:
//!
//! - **Cost**: generation time per view (a run's over its scene's `light_views`) against `1`
//!   and the terms of the technique's [`CostForm`] (triangles, a texel term, per-triangle work
//!   that grows with the map); evaluation time
//!   against `1`, the receivers inside the light's map and the others. Least squares weighted by
//!   `1/sqrt(time)`, between absolute and relative error; a coefficient that comes out negative
//!   is dropped and the rest refitted. The entry's margin is the 95th percentile of
//!   measured over predicted time among its runs.
//! - **Error**: per light kind, the image error against `log2(side)` over the sides from 128 up
//!   (the sides `Auto` chooses among), by least squares over the scenes of that kind.
//!
//! **Validation**, leave one scene out: each catalogue scene in turn is left out of the fit and
//! predicted: the share of its runs whose predicted time is within 1.5x of the measured one; at
//! budgets of 2, 8, 32 and 128 ms, `Auto`'s pick among the configurations run on it (lowest
//! predicted error predicted to fit), the share of picks whose measured time fits, and the
//! regret, the pick's measured error minus the best measured error that fit.

use crate::error::{HarnessError, Result};
use crate::report::json::{Report, Run};
use shadow_frame::{ProfileEntry, SceneSize, TechniqueProfile};
use soft_shadow_core::{Backend, CostForm, LightKind};
use soft_shadow_reference::scenes::catalogue::build;
use std::collections::BTreeMap;

/// Budgets of the validation, milliseconds per light and frame.
pub const VALIDATION_BUDGETS_MS: [f64; 4] = [2.0, 8.0, 32.0, 128.0];

/// The quantile of measured over predicted time that an entry's margin takes.
const MARGIN_QUANTILE: f64 = 0.95;

/// Smallest side the error model is fitted from (the smallest `Auto` chooses).
const ERROR_MIN_SIDE: u32 = 128;

/// Solves the weighted least-squares problem `min Σ w_i (x_i · c - y_i)²` with `c >= 0`
/// (coefficients that come out negative are fixed at 0 and the rest refitted).
fn nonnegative_least_squares(rows: &[(Vec<f64>, f64, f64)], n: usize) -> Vec<f64> {
    let mut active: Vec<bool> = vec![true; n];
    loop {
        let idx: Vec<usize> = (0..n).filter(|&i| active[i]).collect();
        let m = idx.len();
        let mut c = vec![0.0; n];
        if m == 0 {
            return c;
        }
        let sol = match solve(normal_equations(rows, &idx)) {
            Ok(sol) => sol,
            // A column the earlier ones already span (a feature that never varies, or varies
            // with another): drop it.
            Err(dependent) => {
                active[idx[dependent]] = false;
                continue;
            }
        };
        for (r, &i) in idx.iter().enumerate() {
            c[i] = sol[r];
        }
        match idx.iter().find(|&&i| c[i] < 0.0) {
            Some(&i) => active[i] = false,
            None => return c,
        }
    }
}

/// The normal equations of weighted least squares over the columns `idx` of `rows` (`(x, y,
/// weight)`), as an augmented matrix for [`solve`].
fn normal_equations(rows: &[(Vec<f64>, f64, f64)], idx: &[usize]) -> Vec<Vec<f64>> {
    let m = idx.len();
    let mut a = vec![vec![0.0f64; m + 1]; m];
    for (x, y, w) in rows {
        for (r, &i) in idx.iter().enumerate() {
            for (k, &j) in idx.iter().enumerate() {
                a[r][k] += w * x[i] * x[j];
            }
            a[r][m] += w * x[i] * y;
        }
    }
    a
}

/// Gaussian elimination with partial pivoting on an augmented `m x (m + 1)` normal-equation
/// matrix; `Err(k)` when column `k` is (to rounding) a combination of the columns before it.
fn solve(mut a: Vec<Vec<f64>>) -> std::result::Result<Vec<f64>, usize> {
    let m = a.len();
    let diagonal: Vec<f64> = (0..m).map(|i| a[i][i].abs()).collect();
    for col in 0..m {
        let pivot = (col..m)
            .max_by(|&i, &j| a[i][col].abs().total_cmp(&a[j][col].abs()))
            .unwrap_or(col);
        if diagonal[col] == 0.0 || a[pivot][col].abs() <= 1e-9 * diagonal[col] {
            return Err(col);
        }
        a.swap(col, pivot);
        let row = a[col].clone();
        for (i, r) in a.iter_mut().enumerate() {
            if i != col {
                let f = r[col] / row[col];
                for (x, y) in r.iter_mut().zip(&row).skip(col) {
                    *x -= f * y;
                }
            }
        }
    }
    Ok((0..m).map(|i| a[i][m] / a[i][i]).collect())
}

/// What the fit needs to know of a scene.
#[derive(Clone, Copy, Debug)]
struct SceneInfo {
    light: LightKind,
    size: SceneSize,
}

/// The scenes of `report` with their light kind and size: the catalogue's own, and relit
/// catalogue scenes (`scene@kind`). Caster triangles come from the report, or for a report that
/// predates them from the catalogue.
fn scenes(report: &Report) -> BTreeMap<String, SceneInfo> {
    let mut out = BTreeMap::new();
    for r in &report.references {
        let base = r.scene.split('@').next().unwrap_or(&r.scene);
        let Some(light) = LightKind::ALL.into_iter().find(|k| k.name() == r.light) else {
            continue;
        };
        let (triangles, covered) = if r.caster_triangles > 0 {
            (r.caster_triangles, r.covered_receivers)
        } else {
            // A report that predates them: the catalogue's triangles, every receiver covered.
            match build(base).and_then(|s| s.to_scene()) {
                Ok(mut s) => (s.geometry().casters.len(), r.receivers),
                Err(_) => continue,
            }
        };
        out.insert(
            r.scene.clone(),
            SceneInfo {
                light,
                size: SceneSize {
                    triangles,
                    receivers: r.receivers,
                    covered,
                    views: r.light_views,
                },
            },
        );
    }
    out
}

/// The cost form of every configuration the report runs, as its technique states it.
fn cost_forms() -> BTreeMap<(String, String), CostForm> {
    crate::report::options::all_techniques(false)
        .iter()
        .map(|t| ((t.name().to_string(), t.variant()), t.cost_form()))
        .collect()
}

fn backend_of(name: &str) -> Backend {
    if name == "gpu" {
        Backend::Gpu
    } else {
        Backend::Cpu
    }
}

/// Fits one configuration's entry from its runs (each with its scene's info).
fn fit_entry(
    runs: &[(&Run, SceneInfo)],
    forms: &BTreeMap<(String, String), CostForm>,
) -> Option<ProfileEntry> {
    let (first, _) = runs.first()?;
    let form = forms
        .get(&(first.technique.clone(), first.variant.clone()))
        .copied()
        .unwrap_or(CostForm::Texels);
    // Between absolute and relative least squares: measured times carry noise that grows with
    // them, and a prediction within a factor is what matters.
    let weight = |t: f64| 1.0 / t.max(0.05).sqrt();
    let gen_rows: Vec<(Vec<f64>, f64, f64)> = runs
        .iter()
        .map(|(r, s)| {
            // Per view: a light with several views generated each in full.
            let [t1, t2, t3] = form.terms(s.size.triangles, r.resolution);
            let per_view = r.generate_ms / s.size.views.max(1) as f64;
            (vec![1.0, t1, t2, t3], per_view, weight(per_view))
        })
        .collect();
    let eval_rows: Vec<(Vec<f64>, f64, f64)> = runs
        .iter()
        .map(|(r, s)| {
            let outside = s.size.receivers.saturating_sub(s.size.covered);
            (
                vec![1.0, s.size.covered as f64 / 1e6, outside as f64 / 1e6],
                r.evaluate_ms,
                weight(r.evaluate_ms),
            )
        })
        .collect();
    let g = nonnegative_least_squares(&gen_rows, 4);
    let e = nonnegative_least_squares(&eval_rows, 3);
    let in_range: Vec<&(&Run, SceneInfo)> = runs
        .iter()
        .filter(|(r, _)| r.resolution >= ERROR_MIN_SIDE)
        .collect();
    let for_error: Vec<&(&Run, SceneInfo)> = if in_range.is_empty() {
        runs.iter().collect()
    } else {
        in_range
    };
    let lo = for_error.iter().map(|(r, _)| r.resolution).min()?;
    let hi = for_error.iter().map(|(r, _)| r.resolution).max()?;
    let mut error = Vec::new();
    for kind in LightKind::ALL {
        let rows: Vec<(Vec<f64>, f64, f64)> = for_error
            .iter()
            .filter(|(_, s)| s.light == kind)
            .map(|(r, _)| {
                (
                    vec![1.0, (r.resolution as f64).log2()],
                    r.errors.image_rms_255,
                    1.0,
                )
            })
            .collect();
        if rows.is_empty() {
            continue;
        }
        // Unconstrained in sign: an error may grow or fall with the side. With one side
        // measured the log2 column is constant, and the line is the mean.
        let line = match solve(normal_equations(&rows, &[0, 1])) {
            Ok(c) => [c[0], c[1]],
            Err(_) => [
                rows.iter().map(|r| r.1).sum::<f64>() / rows.len() as f64,
                0.0,
            ],
        };
        error.push((kind, line));
    }
    let mut entry = ProfileEntry {
        technique: first.technique.clone(),
        variant: first.variant.clone(),
        backend: backend_of(&first.backend),
        form,
        generate: [g[0], g[1], g[2], g[3]],
        evaluate: [e[0], e[1], e[2]],
        error,
        sides: (lo, hi),
        margin: 1.0,
    };
    let mut ratios: Vec<f64> = runs
        .iter()
        .map(|(r, s)| r.total_ms() / entry.predict_ms(s.size, r.resolution).max(1e-6))
        .collect();
    ratios.sort_by(f64::total_cmp);
    let at = ((ratios.len() as f64 * MARGIN_QUANTILE).ceil() as usize).clamp(1, ratios.len());
    entry.margin = ratios[at - 1].max(1.0);
    Some(entry)
}

/// Whether `scene` is `left_out` or one of its relit forms (`left_out@kind`).
fn belongs_to(scene: &str, left_out: &str) -> bool {
    scene == left_out || scene.split('@').next() == Some(left_out)
}

/// The profile fitted from `report`'s runs on catalogue scenes, leaving out the scene named
/// `left_out` (and its relit forms) where one is given.
pub fn fit(report: &Report, left_out: Option<&str>) -> TechniqueProfile {
    fit_with(report, left_out, &scenes(report), &cost_forms())
}

fn fit_with(
    report: &Report,
    left_out: Option<&str>,
    info: &BTreeMap<String, SceneInfo>,
    forms: &BTreeMap<(String, String), CostForm>,
) -> TechniqueProfile {
    // Runs by configuration: technique, variant, backend.
    type Key = (String, String, String);
    let mut groups: BTreeMap<Key, Vec<(&Run, SceneInfo)>> = BTreeMap::new();
    for r in &report.runs {
        if left_out.is_some_and(|s| belongs_to(&r.scene, s)) {
            continue;
        }
        let Some(s) = info.get(&r.scene) else {
            continue;
        };
        groups
            .entry((r.technique.clone(), r.variant.clone(), r.backend.clone()))
            .or_default()
            .push((r, *s));
    }
    TechniqueProfile {
        entries: groups
            .values()
            .filter_map(|runs| fit_entry(runs, forms))
            .collect(),
    }
}

/// Parses a `report.json` and fits its profile.
pub fn from_report_json(text: &str) -> Result<TechniqueProfile> {
    let report: Report = serde_json::from_str(text)
        .map_err(|e| HarnessError::Usage(format!("not a report.json: {e}")))?;
    Ok(fit(&report, None))
}

/// Reads the `report.json` at `path`.
pub fn read_report(path: &std::path::Path) -> Result<Report> {
    let text = std::fs::read_to_string(path).map_err(|e| {
        HarnessError::Usage(format!(
            "cannot read {}: {e} (run `harness report` first)",
            path.display()
        ))
    })?;
    serde_json::from_str(&text)
        .map_err(|e| HarnessError::Usage(format!("{} is not a report.json: {e}", path.display())))
}

/// The last of `reports` (runs of the same configurations on the same machine), each run's
/// generation and evaluation times the median over the reports that hold the same run (scene,
/// technique, variant, backend and map side): a run slowed by something else on the machine
/// moves a margin (the 95th percentile of measured over predicted time) less. Its errors are
/// the last report's. `None` without reports.
pub fn median_timings(mut reports: Vec<Report>) -> Option<Report> {
    let mut last = reports.pop()?;
    let key = |r: &crate::report::json::Run| {
        (
            r.scene.clone(),
            r.technique.clone(),
            r.variant.clone(),
            r.backend.clone(),
            r.resolution,
        )
    };
    let others: Vec<std::collections::HashMap<_, (f64, f64)>> = reports
        .iter()
        .map(|r| {
            r.runs
                .iter()
                .map(|run| (key(run), (run.generate_ms, run.evaluate_ms)))
                .collect()
        })
        .collect();
    let median = |mut v: Vec<f64>| {
        v.sort_by(f64::total_cmp);
        let n = v.len();
        if n % 2 == 1 {
            v[n / 2]
        } else {
            0.5 * (v[n / 2 - 1] + v[n / 2])
        }
    };
    for run in &mut last.runs {
        let k = key(run);
        let times: Vec<(f64, f64)> = others
            .iter()
            .filter_map(|o| o.get(&k).copied())
            .chain([(run.generate_ms, run.evaluate_ms)])
            .collect();
        run.generate_ms = median(times.iter().map(|t| t.0).collect());
        run.evaluate_ms = median(times.iter().map(|t| t.1).collect());
    }
    Some(last)
}

/// Reads the `report.json` files at `paths` (several: their [`median_timings`]), writes the
/// fitted profile to `out`, and returns it with its leave-one-scene-out validation (where the
/// report has two or more map sides).
pub fn write(
    paths: &[std::path::PathBuf],
    out: &std::path::Path,
) -> Result<(TechniqueProfile, Option<Validation>)> {
    let reports = paths
        .iter()
        .map(|p| read_report(p))
        .collect::<Result<Vec<_>>>()?;
    let report = median_timings(reports)
        .ok_or_else(|| HarnessError::Usage("no report.json to fit".to_string()))?;
    let profile = fit(&report, None);
    if profile.entries.is_empty() {
        let names: Vec<String> = paths.iter().map(|p| p.display().to_string()).collect();
        return Err(HarnessError::Usage(format!(
            "{} holds no runs on catalogue scenes to fit",
            names.join(", ")
        )));
    }
    crate::files::write_text(out, &profile.to_text())?;
    Ok((profile, validate(&report)))
}

/// How well leave-one-scene-out fits predict the left-out scenes.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Validation {
    /// Runs whose predicted time is within 1.5x of the measured time, and runs predicted.
    pub time_within: (usize, usize),
    /// Per budget: picks whose measured time fits the budget, picks made, scenes with something
    /// that fit but no pick, and the summed regret of the picks (1/255).
    pub budgets: Vec<(f64, usize, usize, usize, f64)>,
}

impl Validation {
    /// Share of predicted times within 1.5x.
    pub fn time_share(&self) -> f64 {
        self.time_within.0 as f64 / self.time_within.1.max(1) as f64
    }
    /// Share of picks within budget, over every budget.
    pub fn within_budget_share(&self) -> f64 {
        let (ok, n) = self
            .budgets
            .iter()
            .fold((0, 0), |a, b| (a.0 + b.1, a.1 + b.2));
        ok as f64 / n.max(1) as f64
    }
    /// Mean regret of the picks, over every budget (1/255).
    pub fn mean_regret(&self) -> f64 {
        let (sum, n) = self
            .budgets
            .iter()
            .fold((0.0, 0), |a, b| (a.0 + b.4, a.1 + b.2));
        sum / n.max(1) as f64
    }
}

/// Leave-one-scene-out validation over the catalogue scenes of `report` (not the relit ones);
/// `None` when the report has fewer than two map sides (the texel term cannot be fitted).
pub fn validate(report: &Report) -> Option<Validation> {
    let mut sides: Vec<u32> = report.runs.iter().map(|r| r.resolution).collect();
    sides.sort_unstable();
    sides.dedup();
    if sides.len() < 2 {
        return None;
    }
    let info = scenes(report);
    let forms = cost_forms();
    let mut v = empty_validation();
    let catalogue: Vec<&str> = report
        .references
        .iter()
        .filter(|r| r.relit_from.is_none())
        .map(|r| r.scene.as_str())
        .collect();
    for scene in catalogue {
        let Some(s) = info.get(scene) else { continue };
        let profile = fit_with(report, Some(scene), &info, &forms);
        score(
            &mut v,
            &profile,
            *s,
            report.runs.iter().filter(|r| r.scene == scene),
        );
    }
    Some(v)
}

/// An empty validation over [`VALIDATION_BUDGETS_MS`].
fn empty_validation() -> Validation {
    Validation {
        budgets: VALIDATION_BUDGETS_MS
            .iter()
            .map(|&b| (b, 0, 0, 0, 0.0))
            .collect(),
        ..Default::default()
    }
}

/// Adds to `v` how `profile` predicts the `runs` of one scene of size and light `s`: each run's
/// time, and at each budget `Auto`'s pick among the runs (lowest predicted error predicted to
/// fit), whether its measured time fits and its regret.
fn score<'r>(
    v: &mut Validation,
    profile: &TechniqueProfile,
    s: SceneInfo,
    runs: impl Iterator<Item = &'r Run>,
) {
    // Each run with its prediction: (run, predicted ms, predicted error, margin).
    let mut predicted: Vec<(&Run, f64, Option<f64>, f64)> = Vec::new();
    for r in runs {
        let Some(e) = profile.entries.iter().find(|e| {
            e.technique == r.technique
                && e.variant == r.variant
                && e.backend == backend_of(&r.backend)
        }) else {
            continue;
        };
        let t = e.predict_ms(s.size, r.resolution);
        let measured = r.total_ms();
        v.time_within.1 += 1;
        if t <= 1.5 * measured && measured <= 1.5 * t {
            v.time_within.0 += 1;
        }
        let err = (r.resolution >= ERROR_MIN_SIDE)
            .then(|| e.predict_error(s.light, r.resolution))
            .flatten();
        predicted.push((r, t, err, e.margin));
    }
    for backend in ["cpu", "gpu"] {
        let on: Vec<&(&Run, f64, Option<f64>, f64)> = predicted
            .iter()
            .filter(|p| p.0.backend == backend)
            .collect();
        if on.is_empty() {
            continue;
        }
        for b in v.budgets.iter_mut() {
            let budget = b.0;
            let best_fit = on
                .iter()
                .filter(|p| p.0.total_ms() <= budget && p.0.resolution >= ERROR_MIN_SIDE)
                .map(|p| p.0.errors.image_rms_255)
                .min_by(f64::total_cmp);
            let pick = on
                .iter()
                .filter(|p| p.1 * p.3 <= budget)
                .filter_map(|p| p.2.map(|e| (p, e)))
                .min_by(|a, b| a.1.total_cmp(&b.1).then(a.0.1.total_cmp(&b.0.1)));
            match pick {
                Some((p, _)) => {
                    b.2 += 1;
                    if p.0.total_ms() <= budget {
                        b.1 += 1;
                    }
                    if let Some(best) = best_fit {
                        b.4 += (p.0.errors.image_rms_255 - best).max(0.0);
                    }
                }
                None if best_fit.is_some() => b.3 += 1,
                None => {}
            }
        }
    }
}

/// How `profile` predicts every scene of `report` (scenes it was not fitted on: user scene
/// files, `harness report --scene-file`).
pub fn held_out(profile: &TechniqueProfile, report: &Report) -> Validation {
    let mut v = empty_validation();
    for (scene, s) in scenes(report) {
        score(
            &mut v,
            profile,
            s,
            report.runs.iter().filter(|r| r.scene == scene),
        );
    }
    v
}

/// The validation as a Markdown section of `report.md`.
pub fn markdown(v: Option<&Validation>) -> String {
    let mut s = String::from(
        "## Auto: predictions on scenes left out\n\nEach catalogue scene in turn is left out of the \
         profile fit (`harness profile`: per configuration, generation time against triangles and \
         texels, evaluation against receivers, image error against log2 of the map side per light \
         kind) and predicted. Goals: 90% of predicted times within 1.5x, 95% of `Auto`'s picks \
         within budget, mean regret (the pick's image error minus the best that fit) under 3/255.\n\n",
    );
    let Some(v) = v else {
        s.push_str("This run measured one map side: the validation needs two or more.\n");
        return s;
    };
    s.push_str(&format!(
        "Predicted times within 1.5x of measured: {:.1}% of {} runs (goal 90%).\n\n\
         | budget ms | picks | within budget | mean regret /255 | scenes where something fit but \
         nothing was predicted to |\n|---:|---:|---:|---:|---:|\n",
        100.0 * v.time_share(),
        v.time_within.1
    ));
    for &(budget, ok, n, missed, regret) in &v.budgets {
        s.push_str(&format!(
            "| {budget} | {n} | {:.1}% | {:.2} | {missed} |\n",
            100.0 * ok as f64 / n.max(1) as f64,
            regret / n.max(1) as f64
        ));
    }
    s.push_str(&format!(
        "\nOver every budget: {:.1}% of picks within budget (goal 95%), mean regret {:.2}/255 \
         (goal under 3).\n",
        100.0 * v.within_budget_share(),
        v.mean_regret()
    ));
    s
}
