//! `report.md`: the tables a person reads.

use super::json::Report;
use std::fmt::Write;

/// Renders the report as Markdown.
pub fn render(report: &Report) -> String {
    let mut s = String::new();
    let _ = writeln!(s, "# Soft-shadow report\n");
    let _ = writeln!(
        s,
        "Machine: {} ({} threads); GPU: {}.\n\nErrors are on `V * 255` against a ray-traced reference; times are medians in ms.\n",
        report.machine.cpu, report.machine.threads, report.machine.gpu_adapter
    );
    let _ = writeln!(
        s,
        "## References\n\n| scene | samples/px (penumbra) | std error (255, penumbra RMS) | max std error (255) | receivers | penumbra | time ms |\n|---|---:|---:|---:|---:|---:|---:|"
    );
    for r in &report.references {
        let _ = writeln!(
            s,
            "| {} | {} | {:.3} | {:.3} | {} | {} | {:.0} |",
            r.scene,
            r.samples_per_pixel,
            r.std_error_255,
            r.max_std_error_255,
            r.receivers,
            r.penumbra_receivers,
            r.time_ms
        );
    }
    let mut scenes: Vec<&str> = report.runs.iter().map(|r| r.scene.as_str()).collect();
    scenes.dedup();
    for scene in scenes {
        let cols = report
            .strips
            .iter()
            .find(|st| st.scene == scene)
            .map(|st| st.columns.join(" | "))
            .unwrap_or_default();
        let _ = writeln!(s, "\n## {scene}\n\n![{scene}]({scene}.png)\n");
        let _ = writeln!(
            s,
            "Columns: {cols}. Bottom row: signed error (red: darker than the reference, blue: brighter; full colour at 64/255).\n"
        );
        let _ = writeln!(
            s,
            "| technique | variant | backend | res | gen ms | eval ms | rms | penumbra rms | max abs | nonfinite |\n|---|---|---|---:|---:|---:|---:|---:|---:|---:|"
        );
        for r in report.runs.iter().filter(|r| r.scene == scene) {
            let e = &r.errors;
            let _ = writeln!(
                s,
                "| {} | {} | {} | {} | {:.2} | {:.2} | {:.2} | {:.2} | {:.1} | {} |",
                r.technique,
                r.variant,
                r.backend,
                r.resolution,
                r.generate_ms,
                r.evaluate_ms,
                e.rms_255,
                e.penumbra_rms_255,
                e.max_abs_255,
                e.nonfinite
            );
        }
        let _ = writeln!(s, "\n![pareto {scene}](pareto-{scene}.png)");
    }
    s
}
