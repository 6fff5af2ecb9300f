//! The report's stability tables: `flicker_255` per configuration on the flicker scenes, and the
//! false-shadow (acne) count per technique on `acne` and its relit variants.

use super::json::Report;
use std::collections::BTreeMap;

/// Name of the acne scene; its relit variants are `acne@<kind>`.
pub const ACNE: &str = "acne";

/// `flicker_255` per `technique variant backend`, one column per flicker scene (in
/// [`super::flicker::SCENES`] order; `None` where not measured).
pub fn flicker_rows(report: &Report) -> BTreeMap<String, Vec<Option<f64>>> {
    let scenes = super::flicker::SCENES;
    let mut rows: BTreeMap<String, Vec<Option<f64>>> = BTreeMap::new();
    for r in &report.runs {
        let (Some(f), Some(col)) = (r.flicker_255, scenes.iter().position(|s| *s == r.scene))
        else {
            continue;
        };
        let row = rows
            .entry(format!("{} {} {}", r.technique, r.variant, r.backend))
            .or_insert_with(|| vec![None; scenes.len()]);
        row[col] = Some(f);
    }
    rows
}

/// Acne per `technique variant`: the largest false-shadow count over every resolution and
/// backend on `acne` or a relit `acne@kind`, with the scene it came from and the runs counted.
pub fn acne_rows(report: &Report) -> BTreeMap<String, (u64, String, usize)> {
    let mut rows: BTreeMap<String, (u64, String, usize)> = BTreeMap::new();
    for r in report
        .runs
        .iter()
        .filter(|r| r.scene.split('@').next() == Some(ACNE))
    {
        let e = rows
            .entry(format!("{} {}", r.technique, r.variant))
            .or_insert((0, r.scene.clone(), 0));
        if r.errors.false_shadow_pixels > e.0 {
            e.0 = r.errors.false_shadow_pixels;
            e.1 = r.scene.clone();
        }
        e.2 += 1;
    }
    rows
}
