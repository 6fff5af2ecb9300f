//! Error-vs-time charts (log axes), one line per technique/variant/backend, Pareto front ringed.

use super::json::Run;
use plotters::prelude::*;
use shadow_core::{Result, ShadowError};
use std::collections::BTreeMap;
use std::path::Path;
use std::sync::Once;

/// A map resolution and its (time, error) point.
type ResolutionPoint = (u32, (f64, f64));

static FONT: Once = Once::new();
const DEJAVU: &[u8] = include_bytes!("../../../../assets/DejaVuSans.ttf");

fn register_font() {
    FONT.call_once(|| {
        let _ = plotters::style::register_font("sans-serif", FontStyle::Normal, DEJAVU);
    });
}

fn plot_err(path: &Path, e: impl std::fmt::Display) -> ShadowError {
    ShadowError::Io {
        path: path.display().to_string(),
        source: std::io::Error::other(e.to_string()),
    }
}

/// Indices of the runs on the Pareto front of (total time, rms): no other run is both faster and more accurate.
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

/// Draws `runs` (one scene, or scene-averaged points) to `path`.
pub fn draw(path: &Path, title: &str, runs: &[Run]) -> Result<()> {
    register_font();
    let pts: Vec<(f64, f64)> = runs
        .iter()
        .map(|r| (r.total_ms().max(1e-3), r.errors.rms_255.max(1e-2)))
        .collect();
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
    let root = BitMapBackend::new(path, (1000, 700)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| plot_err(path, e))?;
    let mut chart = ChartBuilder::on(&root)
        .caption(title, ("sans-serif", 24))
        .margin(15)
        .x_label_area_size(45)
        .y_label_area_size(60)
        .build_cartesian_2d(xmin - xpad..xmax + xpad, ymin - ypad..ymax + ypad)
        .map_err(|e| plot_err(path, e))?;
    chart
        .configure_mesh()
        .x_desc("total time per frame (generate + evaluate), ms, log scale")
        .y_desc("rms error of V*255, log scale")
        .x_label_formatter(&|v| format!("{:.3}", 10f64.powf(*v)))
        .y_label_formatter(&|v| format!("{:.2}", 10f64.powf(*v)))
        .draw()
        .map_err(|e| plot_err(path, e))?;
    let mut series: BTreeMap<String, Vec<ResolutionPoint>> = BTreeMap::new();
    for (r, p) in runs.iter().zip(&lg) {
        series
            .entry(r.series())
            .or_default()
            .push((r.resolution, *p));
    }
    for (k, (name, mut v)) in series.into_iter().enumerate() {
        v.sort_by_key(|x| x.0);
        let color = Palette99::pick(k).to_rgba();
        let line: Vec<(f64, f64)> = v.iter().map(|x| x.1).collect();
        chart
            .draw_series(LineSeries::new(line.clone(), color.stroke_width(2)))
            .map_err(|e| plot_err(path, e))?
            .label(name)
            .legend(move |(x, y)| {
                PathElement::new(vec![(x, y), (x + 18, y)], color.stroke_width(2))
            });
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
        .map_err(|e| plot_err(path, e))?
        .label("Pareto front")
        .legend(|(x, y)| Circle::new((x + 9, y), 5, BLACK.stroke_width(2)));
    chart
        .configure_series_labels()
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .position(SeriesLabelPosition::UpperRight)
        .draw()
        .map_err(|e| plot_err(path, e))?;
    root.present().map_err(|e| plot_err(path, e))
}
