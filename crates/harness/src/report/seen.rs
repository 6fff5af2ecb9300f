//! The report's "as seen" section: every technique's `V` over the frame a person looks at
//! ([`crate::as_seen`]: 1280 x 720, maps at the report's sides), with FLIP and the artefacts
//! counted there.

use super::json::SeenRun;
use super::options::ReportOptions;
use super::progress::Progress;
use crate::as_seen::{artefacts, flip, frame, picture, shaded};
use crate::error::{HarnessError, Result};
use soft_shadow_core::{Backend, Context};
use soft_shadow_reference::scenes::catalogue::{AS_SEEN_NAMES, build};
use soft_shadow_reference::scenes::{SceneSpec, scene_file};

/// The scenes measured as seen: those `--as-seen` names (any catalogue scene or scene file);
/// without it, the bunny and [`AS_SEEN_NAMES`] in the full report, the bunny with `--quick`;
/// with `--scenes`, those of them named; none for scene files alone.
pub fn scene_names(opts: &ReportOptions) -> Vec<String> {
    if let Some(asked) = &opts.as_seen {
        let mut names: Vec<String> = Vec::new();
        for n in asked {
            if !names.contains(n) {
                names.push(n.clone());
            }
        }
        return names;
    }
    let meshes = std::iter::once("bunny").chain(AS_SEEN_NAMES);
    match &opts.scenes {
        Some(asked) => meshes
            .filter(|n| asked.iter().any(|a| a == n))
            .map(str::to_string)
            .collect(),
        None if !opts.scene_files.is_empty() => Vec::new(),
        None if opts.quick => vec!["bunny".to_string()],
        None => meshes.map(str::to_string).collect(),
    }
}

/// How many steps [`measure`] counts on the progress bar for `scenes` with `techniques` on
/// `backends` backends: a reference per scene and a step per configuration.
pub fn steps(
    opts: &ReportOptions,
    scenes: &[SceneSpec],
    techniques: &[soft_shadow_core::Technique],
    backends: usize,
) -> u64 {
    scenes
        .iter()
        .map(|spec| {
            let modelled = techniques
                .iter()
                .filter(|t| t.models(spec.light.kind()))
                .count();
            1 + (modelled * opts.resolutions().len() * backends) as u64
        })
        .sum()
}

/// The scenes of [`scene_names`]: a scene file's of that name, else the catalogue's; a name
/// that is neither is an error that names it and what it may be.
pub fn specs(opts: &ReportOptions) -> Result<Vec<SceneSpec>> {
    let names = scene_names(opts);
    let files = if opts.as_seen.is_some() {
        opts.scene_files
            .iter()
            .map(|f| scene_file::load(f))
            .collect::<std::result::Result<Vec<_>, _>>()?
    } else {
        Vec::new()
    };
    names
        .iter()
        .map(|n| match files.iter().find(|s| &s.name == n) {
            Some(spec) => Ok(spec.clone()),
            None => build(n).map_err(|_| {
                HarnessError::Usage(format!(
                    "--as-seen: no scene named {n:?} (a built-in scene, `report --list`, or the \
                     name of a --scene-file's scene)"
                ))
            }),
        })
        .collect()
}

/// The file of a scene's picture in the output folder: `as-seen-<scene>.png`.
pub fn picture_file(scene: &str) -> String {
    format!("as-seen-{}.png", super::file_stem(scene))
}

/// The folder of a scene's full-size shaded frames in the output folder: `as-seen-<scene>/`,
/// holding `reference.png` and `<technique>-<variant>.png` for each technique pictured, the
/// images FLIP compared (to check it with another FLIP implementation).
pub fn frames_dir(scene: &str) -> String {
    format!("as-seen-{}", super::file_stem(scene))
}

/// Every technique of `techniques` that models the scene's light, at every map side of the
/// report, on `backends`, over the frame of each of `scenes` ([`specs`]); a configuration that
/// fails is recorded in `skipped` (and printed above `bar`). Per scene, [`picture_file`] in `opts.out` shows the reference's
/// shaded frame, then for the first variant of each technique on the first backend (its family's default where the registry runs it), at the side
/// nearest 1024, its frame with the artefacts marked
/// ([`crate::as_seen::picture`]) beside its FLIP map, at half size; [`frames_dir`] holds the
/// full-size frames.
pub fn measure(
    opts: &ReportOptions,
    scenes: Vec<SceneSpec>,
    techniques: &[soft_shadow_core::Technique],
    contexts: &[(Backend, Context<'_>)],
    bar: &mut Progress,
    skipped: &mut Vec<String>,
) -> Result<Vec<SeenRun>> {
    let mut runs = Vec::new();
    for spec in scenes {
        let name = spec.name.clone();
        bar.set_message(format!("{name} as seen: reference"));
        let scene = frame(spec)?;
        super::refuse_uncovered(&name, &scene)?;
        bar.inc();
        let light = &scene.spec.light;
        let dir = opts.out.join(frames_dir(&name));
        crate::files::create_dir(&dir)?;
        let reference = scene.reference_v();
        save(&dir.join("reference.png"), &shaded(&scene, &reference))?;
        let mut rows = vec![(picture(&scene, &reference), None)];
        let mut pictured: Vec<&str> = Vec::new();
        let resolutions = opts.resolutions();
        // The pictures show the side nearest 1024, the side people use in a viewer.
        let pictured_side = resolutions
            .iter()
            .copied()
            .min_by_key(|r| (*r as i64 - 1024).abs())
            .unwrap_or(0);
        for t in techniques.iter().filter(|t| t.models(light.kind())) {
            for &resolution in &resolutions {
                for (i, &(backend, ctx)) in contexts.iter().enumerate() {
                    let label = format!(
                        "{name} as seen {} {} {resolution} {backend:?}",
                        t.name(),
                        t.variant()
                    );
                    bar.set_message(label.clone());
                    let gpu = match ctx {
                        Context::Gpu(g) => Some(g),
                        Context::Cpu(_) => None,
                    };
                    let v = match t
                        .generate_in(ctx, &scene.geometry, light, &scene.views, resolution)
                        .and_then(|m| m.evaluate(gpu, &scene.receivers()))
                    {
                        Ok(v) => v,
                        Err(e) => {
                            super::skip(bar, skipped, label, &e);
                            bar.inc();
                            continue;
                        }
                    };
                    bar.inc();
                    let (score, heat) = flip(&scene, &v);
                    if i == 0 && resolution == pictured_side && !pictured.contains(&t.name()) {
                        pictured.push(t.name());
                        let file = format!(
                            "{}-{}.png",
                            super::file_stem(t.name()),
                            super::file_stem(&t.variant())
                        );
                        save(&dir.join(file), &shaded(&scene, &v))?;
                        let (w, h) = heat.dimensions();
                        let half = image::imageops::thumbnail(&heat, w.div_ceil(2), h.div_ceil(2));
                        rows.push((picture(&scene, &v), Some(half)));
                    }
                    let a = artefacts(&scene, &v);
                    runs.push(SeenRun {
                        scene: name.clone(),
                        light: light.kind().name().to_string(),
                        technique: t.name().to_string(),
                        variant: t.variant(),
                        backend: format!("{backend:?}").to_lowercase(),
                        resolution,
                        receivers: a.receivers,
                        darkened: a.darkened,
                        false_umbra_per_million: a.per_million(a.false_umbra),
                        leaks_per_million: a.per_million(a.leaks),
                        object_leaks_per_million: a.per_million(a.object_leaks),
                        flip_mean: score.mean,
                        flip_p95: score.p95,
                        image_rms_255: crate::metrics::image_rms_255(
                            &v,
                            &reference,
                            &scene.shading.weight,
                        ),
                        reference_ms: scene.reference_ms,
                    });
                }
            }
        }
        write_grid(&opts.out.join(picture_file(&name)), &rows)?;
    }
    Ok(runs)
}

/// `img` as PNG at `path`.
fn save(path: &std::path::Path, img: &image::RgbImage) -> Result<()> {
    img.save(path)
        .map_err(|e| crate::error::HarnessError::write(path, e))
}

/// `rows` of two tiles (all of one size; a missing second tile left black), as PNG.
fn write_grid(
    path: &std::path::Path,
    rows: &[(image::RgbImage, Option<image::RgbImage>)],
) -> Result<()> {
    let (w, h) = rows.first().map_or((1, 1), |t| t.0.dimensions());
    let mut grid = image::RgbImage::new(2 * w, rows.len() as u32 * h);
    for (i, (a, b)) in rows.iter().enumerate() {
        let y = i as i64 * h as i64;
        image::imageops::replace(&mut grid, a, 0, y);
        if let Some(b) = b {
            image::imageops::replace(&mut grid, b, w as i64, y);
        }
    }
    save(path, &grid)
}
