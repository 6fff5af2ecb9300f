//! `report.md`: the tables a person reads.

use super::json::Report;
use super::pareto::front_membership;
use super::stability::{ACNE, acne_rows, flicker_rows};
use super::summary::{BUDGETS_MS, SCALING_LIMIT, lines, scaling_cause, scaling_exponents};
use std::fmt::Write;

/// Renders the report as Markdown; `papers_written`: `papers.html` is in the output folder
/// (then linked; otherwise the line says how to write it there).
pub fn render(report: &Report, papers_written: bool) -> String {
    let mut s = String::new();
    let _ = writeln!(s, "# Soft-shadow report\n");
    let _ = writeln!(
        s,
        "Machine: {} ({} threads); GPU: {}.\n\nErrors are against a ray-traced reference (`V`: the fraction of the light points above a receiver's tangent plane, on the light's emitting side, that it sees; receivers no light point reaches are *unlit*, counted per scene, hatched in the strips and in no error). **Image error** (`image`), what everything here ranks by, is the rms of `(V - V_ref) * E0 / E0_max * 255`, with `E0` the light's unshadowed irradiance at the receiver and `E0_max` the scene's brightest: the error a white Lambertian scene lit by the light shows. `V` rms is the error of the visibility alone, which the papers' ground-plane tables use. Times are medians in ms.\n",
        report.machine.cpu, report.machine.threads, report.machine.gpu_adapter
    );
    if papers_written {
        let _ = writeln!(
            s,
            "[Each paper's own experiment beside its published numbers: papers.html](papers.html)\n"
        );
    } else {
        let _ = writeln!(
            s,
            "Each paper's own experiment beside its published numbers: `cargo run --release --bin harness -- papers --out` this folder writes `papers.html` here.\n"
        );
    }
    summary(&mut s, report);
    as_seen(&mut s, report);
    lamps(&mut s, report);
    s.push_str(&crate::profile::markdown(
        crate::profile::validate(report).as_ref(),
    ));
    s.push('\n');
    let _ = writeln!(
        s,
        "## References\n\n`scene@kind` is a hard case recast under a light of that kind, for the techniques that do not model its own light (see `soft_shadow_reference::scenes::relight`).\n\nA receiver is proven lit (error 0) when no caster crosses the hull of it and the light; every other one gets the stated samples, and its error is the replicates' standard error, or where every ray agreed the 99% bound on a feature the rays could miss: \"max error\" is the reference's true worst error. \"views\" are the light's views every technique generates maps for (one frustum, cube faces or cascades).\n\n| scene | light | views | samples/px (not proven lit) | std error (255, penumbra RMS) | max error (255) | receivers | unlit | penumbra | time ms |\n|---|---|---|---:|---:|---:|---:|---:|---:|---:|"
    );
    for r in &report.references {
        let _ = writeln!(
            s,
            "| {} | {} | {} {} | {} | {:.3} | {:.3} | {} | {} | {} | {:.0} |",
            r.scene,
            r.light,
            r.light_views,
            r.view_kind,
            r.samples_per_pixel,
            r.std_error_255,
            r.max_std_error_255,
            r.receivers,
            r.unlit_receivers,
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
        let _ = writeln!(
            s,
            "\n## {scene}\n\n![{scene}]({}.png)\n",
            super::file_stem(scene)
        );
        let _ = writeln!(
            s,
            "Columns: {cols}. Rows: `V`; the shaded image `E0 V / E0_max`; its signed error (red: darker than the reference, blue: brighter; full colour at 64/255). `ground`, `object` and `terminator` split the image error by where the receivers lie: on geometry that only receives, on the casters, and where the normal is within about 17 degrees of perpendicular to the light (cos < 0.3); `near`, `mid` and `far` by their distance from the camera: under 15 m, 15 to 60 m, beyond (blank where none lies there). `gen ms` generates the maps of every view of the light, `gen ms per view` is its share per view.\n"
        );
        let _ = writeln!(
            s,
            "| technique | variant | backend | res | gen ms | gen ms per view | eval ms | image | image penumbra | V rms | V penumbra | ground | object | terminator | near | mid | far | max abs | false-shadow px | flicker | nonfinite |\n|---|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"
        );
        // The maps of every view of the scene's light (its recast light's, on `scene@kind`).
        let views = report
            .references
            .iter()
            .find(|r| r.scene == scene)
            .map_or(1, |r| r.light_views.max(1));
        for r in report.runs.iter().filter(|r| r.scene == scene) {
            let e = &r.errors;
            let _ = writeln!(
                s,
                "| {} | {} | {} | {} | {:.2} | {:.2} | {:.2} | {:.2} | {:.2} | {:.2} | {:.2} | {} | {} | {} | {} | {} | {} | {:.1} | {} | {} | {} |",
                r.technique,
                r.variant,
                r.backend,
                r.resolution,
                r.generate_ms,
                r.generate_ms / views as f64,
                r.evaluate_ms,
                e.image_rms_255,
                e.image_penumbra_rms_255,
                e.rms_255,
                e.penumbra_rms_255,
                class(&e.classes.ground),
                class(&e.classes.object),
                class(&e.classes.terminator),
                class(&e.classes.near),
                class(&e.classes.mid),
                class(&e.classes.far),
                e.max_abs_255,
                e.false_shadow_pixels,
                r.flicker_255.map(|f| format!("{f:.2}")).unwrap_or_default(),
                e.nonfinite
            );
        }
        let _ = writeln!(
            s,
            "\n![pareto {scene}](pareto-{}.png)",
            super::file_stem(scene)
        );
    }
    s
}

/// One class's image error, or blank when the class is empty.
fn class(c: &crate::metrics::ClassErrors) -> String {
    if c.pixels == 0 {
        String::new()
    } else {
        format!("{:.2}", c.image_rms_255)
    }
}

/// The summary table: per light kind and budget, the best configuration here and its margin
/// over the best baseline; then the generation scaling exponents.
fn summary(s: &mut String, report: &Report) {
    let _ = writeln!(
        s,
        "## Summary\n\nPer light kind and per-light budget (generation + evaluation, mean over the \
         scenes of that kind), the configuration with the lowest mean image error \
         (`image_rms_255`) here, and the best baseline (hard shadow map, PCF, PCSS, \
         accumulation) in the same budget, leaving out any configuration a person sees as \
         worse than the hard shadow map by FLIP (As seen). Budgets: {:?} ms.\n",
        BUDGETS_MS
    );
    let _ = writeln!(
        s,
        "| light | budget ms | best here | image | V rms | ms | best baseline | image | better by |\n|---|---:|---|---:|---:|---:|---|---:|---:|"
    );
    for l in lines(report) {
        let cell = |c: &Option<super::summary::Config>| match c {
            Some(c) => format!(
                "{} | {:.2} | {:.2} | {:.2}",
                c.label, c.image_rms_255, c.rms_255, c.time_ms
            ),
            None => "none fits | | | ".to_string(),
        };
        let margin = match (&l.best, &l.baseline) {
            (Some(b), Some(base)) => format!("{:.2}", base.image_rms_255 - b.image_rms_255),
            _ => String::new(),
        };
        let best = cell(&l.best);
        let base = match &l.baseline {
            Some(c) => format!("{} | {:.2}", c.label, c.image_rms_255),
            None => "none fits | ".to_string(),
        };
        let _ = writeln!(
            s,
            "| {} | {} | {best} | {base} | {margin} |",
            l.light, l.budget_ms
        );
    }
    stability(s, report);
    fronts(s, report);
    let _ = writeln!(
        s,
        "\nEvery configuration, mean image error against mean time over the scenes (log axes, Pareto front ringed):\n\n![all scenes: mean error vs mean time](pareto.png)"
    );
    scaling(s, report);
    super::cost::markdown(s, report);
    s.push('\n');
}

/// Flicker and acne tables.
fn stability(s: &mut String, report: &Report) {
    let rows = flicker_rows(report);
    if !rows.is_empty() {
        let scenes = super::flicker::SCENES;
        let _ = writeln!(
            s,
            "\n## Temporal stability\n\n`flicker_255`: the light moves {} cm per frame; the mean \
             excess frame-to-frame change of `V` over the reference's own change, times 255 (0 = \
             follows the light exactly).\n\n| configuration | {} |\n|---|{}",
            super::flicker::STEP * 100.0,
            scenes.join(" | "),
            "---:|".repeat(scenes.len())
        );
        for (k, v) in rows {
            let cells: Vec<String> = v
                .iter()
                .map(|f| f.map(|f| format!("{f:.2}")).unwrap_or_default())
                .collect();
            let _ = writeln!(s, "| {k} | {} |", cells.join(" | "));
        }
    }
    let acne = acne_rows(report);
    if !acne.is_empty() {
        let _ = writeln!(
            s,
            "\n## Acne\n\nOn `{ACNE}` (unoccluded receivers at grazing light; `{ACNE}@kind`: the \
             same under a recast light for techniques that do not model a distant one), the \
             largest count over resolutions and backends of receivers the reference sees lit \
             (`V_ref >= 0.98`) that come out below 0.98. Every entry should be 0.\n\n\
             | technique variant | false-shadow px (worst) | worst on | runs |\n|---|---:|---|---:|"
        );
        for (k, (n, scene, runs)) in acne {
            let _ = writeln!(s, "| {k} | {n} | {scene} | {runs} |");
        }
    }
}

/// Which scenes' Pareto fronts each technique reaches.
fn fronts(s: &mut String, report: &Report) {
    let m = front_membership(report);
    if m.is_empty() {
        return;
    }
    let _ = writeln!(
        s,
        "\n## Pareto fronts\n\nPer technique, the scenes where one of its runs (any variant, \
         backend, resolution) is on the front of image error against total time: nothing else is both \
         faster and more accurate there.\n\n| technique | on the front of | scenes |\n|---|---|---:|"
    );
    for (t, scenes) in m {
        let list = if scenes.is_empty() {
            "never".to_string()
        } else {
            scenes.join(", ")
        };
        let _ = writeln!(s, "| {t} | {list} | {} |", scenes.len());
    }
}

/// Generation-time exponents, with the cause of any above [`SCALING_LIMIT`].
fn scaling(s: &mut String, report: &Report) {
    let exps = scaling_exponents(report);
    if exps.is_empty() {
        return;
    }
    let _ = writeln!(
        s,
        "\n## Scaling\n\nSlope of log(generation time) against log(texels) over the resolutions \
         256..2048 measured (1 = linear in texels; fixed costs pull it below 1). Above \
         {SCALING_LIMIT}, the cause.\n\n| configuration | exponent | resolutions | why above {SCALING_LIMIT} |\n|---|---:|---:|---|"
    );
    for (k, e, n) in exps {
        let why = if e > SCALING_LIMIT {
            scaling_cause(&k)
        } else {
            ""
        };
        let _ = writeln!(s, "| {k} | {e:.2} | {n} | {why} |");
    }
}

/// The "as seen" section: per scene, every technique's artefacts over the viewing frame.
fn as_seen(s: &mut String, report: &Report) {
    use crate::as_seen::{ARTEFACT_STEP, HEIGHT, ISOLATION, PIXELS_PER_DEGREE, WIDTH};
    if report.as_seen.is_empty() {
        return;
    }
    let _ = writeln!(
        s,
        "\n## As seen\n\nThe frame a person looks at ({WIDTH} x {HEIGHT}, the reference at \
         128 rays per receiver not proven lit), at every map side of the report. **FLIP**: NVIDIA's perceptual \
         difference of the shaded frame (`V E0 / E0_max`, sRGB) from the reference's at \
         {PIXELS_PER_DEGREE:.0} pixels per degree, mean and 95th percentile over the receivers; \
         **worse than hard** marks a configuration whose mean FLIP is above the hard shadow \
         map's on the same scene, backend and map side: `choose` never recommends it. **darkened** counts receivers the reference sees \
         at least half lit drawn at less than half of it (blotches, streaks, rings); **false \
         umbra** receivers darker by more than {ARTEFACT_STEP} of the light where the \
         reference is lit within {ISOLATION} pixels; **leaks** lighter by as much where it is \
         umbra within {ISOLATION} pixels (on objects: light specks on a caster's shadowed \
         side), per million receivers. The small G-buffers' rms above does not rank these."
    );
    let mut scenes: Vec<&str> = report.as_seen.iter().map(|r| r.scene.as_str()).collect();
    scenes.dedup();
    for scene in scenes {
        let runs: Vec<_> = report.as_seen.iter().filter(|r| r.scene == scene).collect();
        let mut shown: Vec<&str> = Vec::new();
        // The picture's rows: each technique's first run on the first backend.
        for r in runs.iter().filter(|r| r.backend == runs[0].backend) {
            if !shown.contains(&r.technique.as_str()) {
                shown.push(&r.technique);
            }
        }
        let _ = writeln!(
            s,
            "\n### {scene} as seen\n\n![{scene} as seen]({})\n\nTop: the reference. Then one row each for {} (its default variant, at the side nearest 1024²): the frame, red where darker than the reference by 1/4 of the light, blue where lighter; beside it the FLIP map (magma: black is no visible difference). Full-size frames: `{}/`.\n\n{} receivers; reference {:.1} s.\n\n| technique | variant | backend | side | FLIP mean | FLIP p95 | image /255 | darkened (px) | false umbra /M | leaks /M | on objects /M |\n|---|---|---|---:|---:|---:|---:|---:|---:|---:|---:|",
            super::seen::picture_file(scene),
            shown.join(", "),
            super::seen::frames_dir(scene),
            runs[0].receivers,
            runs[0].reference_ms / 1e3
        );
        let hard = |backend: &str, side: u32| {
            runs.iter()
                .find(|r| {
                    r.technique == "hard-shadow-map" && r.backend == backend && r.resolution == side
                })
                .map(|r| r.flip_mean)
        };
        for r in &runs {
            let worse = hard(&r.backend, r.resolution).is_some_and(|h| r.flip_mean > h);
            let _ = writeln!(
                s,
                "| {} | {} | {} | {}² | {:.4}{} | {:.3} | {:.2} | {} | {:.0} | {:.0} | {:.0} |",
                r.technique,
                r.variant,
                r.backend,
                r.resolution,
                r.flip_mean,
                if worse { " (worse than hard)" } else { "" },
                r.flip_p95,
                r.image_rms_255,
                r.darkened,
                r.false_umbra_per_million,
                r.leaks_per_million,
                r.object_leaks_per_million
            );
        }
    }
    s.push('\n');
}

/// The scenes of many lamps: per walk, its frames' times against the budget and its frames'
/// image errors, with its document.
fn lamps(s: &mut String, report: &Report) {
    if report.frames.is_empty() {
        return;
    }
    let _ = writeln!(
        s,
        "\n## Scenes of many lamps\n\nEach scene walked by the frame pipeline (CPU) under one \
         frame budget shared by its lamps: the frames' measured times (the first allocates the \
         maps), how many ran over the budget, and the image error of each frame's summed \
         lighting against the reference beside the same with no shadow. Every frame and every \
         lamp's pick and error: the scene's document.\n\n| scene | lamps | budget ms | \
         receivers | frames | measured ms (after the first) | first frame ms | over the budget | \
         frame image error | with no shadow | document |\n|---|---:|---:|---|---:|---|---:|---:|\
         ---|---|---|"
    );
    let range = |v: Vec<f64>| {
        let lo = v.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = v.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        if v.is_empty() {
            "–".to_string()
        } else {
            format!("{lo:.2}-{hi:.2}")
        }
    };
    for r in &report.frames {
        let file = super::lamps::file(&r.scene);
        let _ = writeln!(
            s,
            "| {} | {} | {} | {}x{} | {} | {} | {} | {} | {} | {} | [{file}]({file}) |",
            r.scene,
            r.lamps,
            r.budget_ms,
            r.size.0,
            r.size.1,
            r.frames.len(),
            range(r.frames.iter().skip(1).map(|f| f.ms).collect()),
            r.frames
                .first()
                .map_or("–".to_string(), |f| format!("{:.2}", f.ms)),
            r.over_budget(),
            range(r.frames.iter().map(|f| f.image_255).collect()),
            range(r.frames.iter().map(|f| f.no_shadow_255).collect()),
        );
    }
}
