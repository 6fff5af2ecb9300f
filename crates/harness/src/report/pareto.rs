//! Error-vs-time charts (log axes), one line per technique/variant/backend, Pareto front ringed.

use super::json::Run;
use crate::error::{HarnessError, Result};
use plotters::prelude::*;
use std::collections::BTreeMap;
use std::path::Path;
use std::sync::Once;

/// A map resolution and its (time, error) point.
type ResolutionPoint = (u32, (f64, f64));

static FONT: Once = Once::new();
/// Width of the plot, pixels.
const PLOT_WIDTH: u32 = 1000;
/// Width of the legend column, pixels.
const LEGEND_WIDTH: u32 = 420;
/// First legend line's baseline, pixels from the top.
const LEGEND_TOP: u32 = 60;
/// Legend line height, pixels.
const LEGEND_LINE: u32 = 16;
const DEJAVU: &[u8] = include_bytes!("../../../../assets/DejaVuSans.ttf");

pub(crate) fn register_font() {
    FONT.call_once(|| {
        let _ = plotters::style::register_font("sans-serif", FontStyle::Normal, DEJAVU);
    });
}

fn plot_err(path: &Path, e: impl std::fmt::Display) -> HarnessError {
    HarnessError::write(path, e)
}

/// Indices of the runs on the Pareto front of (total time, image rms): no other run is both faster and more accurate.
pub fn pareto_front(points: &[(f64, f64)]) -> Vec<usize> {
    (0..points.len())
        .filter(|&i| {
            !points.iter().enumerate().any(|(j, q)| {
                j != i
                    && q.0 <= points[i].0
                    && q.1 <= points[i].1
                    && (q.0 < points[i].0 || q.1 < points[i].1)
            })
        })
        .collect()
}

/// Chart coordinates of a run: (total ms, image rms), clamped away from 0 for the log axes.
fn point(r: &Run) -> (f64, f64) {
    (r.total_ms().max(1e-3), r.errors.image_rms_255.max(1e-2))
}

/// Per technique, the scenes on whose Pareto front (over every run of the scene: variants,
/// backends, resolutions) at least one of its runs lies; an empty list for a technique never on
/// one. Relit hard cases (`scene@kind`) are left out: only some techniques run there.
pub fn front_membership(report: &super::json::Report) -> BTreeMap<String, Vec<String>> {
    let mut out: BTreeMap<String, Vec<String>> = BTreeMap::new();
    for reference in report.references.iter().filter(|r| r.relit_from.is_none()) {
        let runs: Vec<&Run> = report
            .runs
            .iter()
            .filter(|r| r.scene == reference.scene)
            .collect();
        for r in &runs {
            out.entry(r.technique.clone()).or_default();
        }
        let pts: Vec<(f64, f64)> = runs.iter().map(|r| point(r)).collect();
        for i in pareto_front(&pts) {
            let scenes = out.entry(runs[i].technique.clone()).or_default();
            if !scenes.contains(&reference.scene) {
                scenes.push(reference.scene.clone());
            }
        }
    }
    out
}

/// Draws `runs` (one scene, or scene-averaged points) to `path`.
pub fn draw(path: &Path, title: &str, runs: &[Run]) -> Result<()> {
    register_font();
    let pts: Vec<(f64, f64)> = runs.iter().map(point).collect();
    if pts.is_empty() {
        return Ok(());
    }
    // Log axes drawn as log10 values on linear axes, so every range gets labelled ticks.
    let lg: Vec<(f64, f64)> = pts.iter().map(|p| (p.0.log10(), p.1.log10())).collect();
    let (xmin, xmax) = lg
        .iter()
        .fold((f64::MAX, f64::MIN), |a, p| (a.0.min(p.0), a.1.max(p.0)));
    let (ymin, ymax) = lg
        .iter()
        .fold((f64::MAX, f64::MIN), |a, p| (a.0.min(p.1), a.1.max(p.1)));
    let (xpad, ypad) = (0.1 + 0.05 * (xmax - xmin), 0.1 + 0.05 * (ymax - ymin));
    let mut series: BTreeMap<String, Vec<ResolutionPoint>> = BTreeMap::new();
    for (r, p) in runs.iter().zip(&lg) {
        series
            .entry(r.series())
            .or_default()
            .push((r.resolution, *p));
    }
    // The legend gets its own column right of the plot, one line per series.
    let height = (700u32).max(LEGEND_TOP + LEGEND_LINE * (series.len() as u32 + 2));
    let size = (PLOT_WIDTH + LEGEND_WIDTH, height);
    // Drawn into memory, then encoded by the `image` crate the report writes its strips with
    // (plotters' own encoder would build a second `image` version into every build).
    let mut pixels = vec![0u8; size.0 as usize * size.1 as usize * 3];
    {
        let root = BitMapBackend::with_buffer(&mut pixels, size).into_drawing_area();
        root.fill(&WHITE).map_err(|e| plot_err(path, e))?;
        let (plot, legend) = root.split_horizontally(PLOT_WIDTH);
        let mut chart = ChartBuilder::on(&plot)
            .caption(title, ("sans-serif", 24))
            .margin(15)
            .x_label_area_size(45)
            .y_label_area_size(60)
            .build_cartesian_2d(xmin - xpad..xmax + xpad, ymin - ypad..ymax + ypad)
            .map_err(|e| plot_err(path, e))?;
        chart
            .configure_mesh()
            .x_desc("total time per frame (generate + evaluate), ms, log scale")
            .y_desc("image error (rms of (V - V_ref) E0/E0_max * 255), log scale")
            .x_label_formatter(&|v| format!("{:.3}", 10f64.powf(*v)))
            .y_label_formatter(&|v| format!("{:.2}", 10f64.powf(*v)))
            .draw()
            .map_err(|e| plot_err(path, e))?;
        let font = ("sans-serif", 13).into_font();
        let entry_y = |k: usize| (LEGEND_TOP + LEGEND_LINE * k as u32) as i32;
        for (k, (name, mut v)) in series.into_iter().enumerate() {
            v.sort_by_key(|x| x.0);
            let color = Palette99::pick(k).to_rgba();
            let line: Vec<(f64, f64)> = v.iter().map(|x| x.1).collect();
            chart
                .draw_series(LineSeries::new(line.clone(), color.stroke_width(2)))
                .map_err(|e| plot_err(path, e))?;
            let y = entry_y(k);
            legend
                .draw(&PathElement::new(
                    vec![(8, y), (30, y)],
                    color.stroke_width(3),
                ))
                .map_err(|e| plot_err(path, e))?;
            legend
                .draw(&Text::new(name, (36, y - 7), font.clone()))
                .map_err(|e| plot_err(path, e))?;
            chart
                .draw_series(line.iter().map(|p| Circle::new(*p, 3, color.filled())))
                .map_err(|e| plot_err(path, e))?;
        }
        let front = pareto_front(&pts);
        chart
            .draw_series(
                front
                    .iter()
                    .map(|&i| Circle::new(lg[i], 8, BLACK.stroke_width(2))),
            )
            .map_err(|e| plot_err(path, e))?;
        let y = entry_y(0) - LEGEND_LINE as i32;
        legend
            .draw(&Circle::new((19, y), 6, BLACK.stroke_width(2)))
            .map_err(|e| plot_err(path, e))?;
        legend
            .draw(&Text::new("Pareto front (ringed)", (36, y - 7), font))
            .map_err(|e| plot_err(path, e))?;
        root.present().map_err(|e| plot_err(path, e))?;
    }
    image::RgbImage::from_raw(size.0, size.1, pixels)
        .ok_or_else(|| plot_err(path, "chart buffer of the wrong size"))?
        .save(path)
        .map_err(|e| plot_err(path, e))
}

/// One point per technique/variant/backend/resolution: the mean over scenes of time and error.
pub fn scene_means(runs: &[Run]) -> Vec<Run> {
    let mut out: Vec<(Run, u32)> = Vec::new();
    for r in runs {
        match out
            .iter_mut()
            .find(|(o, _)| o.series() == r.series() && o.resolution == r.resolution)
        {
            Some((o, n)) => {
                o.generate_ms += r.generate_ms;
                o.evaluate_ms += r.evaluate_ms;
                o.errors.rms_255 += r.errors.rms_255;
                o.errors.image_rms_255 += r.errors.image_rms_255;
                *n += 1;
            }
            None => out.push((r.clone(), 1)),
        }
    }
    out.into_iter()
        .map(|(mut o, n)| {
            let k = n as f64;
            o.generate_ms /= k;
            o.evaluate_ms /= k;
            o.errors.rms_255 /= k;
            o.errors.image_rms_255 /= k;
            o.scene = "all".into();
            o
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::pareto_front;

    #[test]
    fn the_front_holds_exactly_the_undominated_points() {
        // (time, error): (3, 6) is dominated by (2, 5), (5, 1) by (4, 1); ties on one axis
        // dominate only when strictly better on the other.
        let pts = [(1.0, 10.0), (2.0, 5.0), (3.0, 6.0), (4.0, 1.0), (5.0, 1.0)];
        assert_eq!(pareto_front(&pts), [0, 1, 3]);
        // Identical points do not dominate each other.
        assert_eq!(pareto_front(&[(1.0, 1.0), (1.0, 1.0)]), [0, 1]);
    }
}
