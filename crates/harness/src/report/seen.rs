//! The report's "as seen" section: every technique's `V` over the frame a person looks at
//! ([`crate::as_seen`]: 1280 x 720, maps at 1024²), with the artefacts counted there.

use super::json::SeenRun;
use super::options::ReportOptions;
use crate::as_seen::{artefacts, frame, picture};
use crate::error::Result;
use crate::scenes::catalogue::{AS_SEEN_NAMES, build};
use soft_shadow_core::{Backend, Context, DynTechnique};

/// The map side the frames are measured at: the side people use in a viewer.
pub const RESOLUTION: u32 = 1024;

/// The scenes measured as seen: the bunny and [`AS_SEEN_NAMES`] in the full report, the bunny
/// with `--quick`; with `--scenes`, those of them named; none for scene files alone.
pub fn scene_names(opts: &ReportOptions) -> Vec<String> {
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

/// The file of a scene's picture in the output folder: `as-seen-<scene>.png`.
pub fn picture_file(scene: &str) -> String {
    format!("as-seen-{}.png", super::file_stem(scene))
}

/// Every technique of `techniques` that models the scene's light, on `backends`, over the frame
/// of each scene of [`scene_names`]; a configuration that fails is recorded by `skip`. Per
/// scene, [`picture_file`] in `opts.out` holds the reference's shaded image, then the first
/// variant of each technique on the first backend ([`crate::as_seen::picture`]), tiles of
/// 640 x 360 two to a row.
pub fn measure(
    opts: &ReportOptions,
    techniques: &[Box<dyn DynTechnique>],
    contexts: &[(Backend, Context<'_>)],
    mut skip: impl FnMut(String, &soft_shadow_core::ShadowError),
) -> Result<Vec<SeenRun>> {
    let mut runs = Vec::new();
    for name in scene_names(opts) {
        let scene = frame(build(&name)?)?;
        let light = &scene.spec.light;
        let mut tiles = vec![picture(&scene, &scene.reference_v())];
        let mut pictured: Vec<&str> = Vec::new();
        for t in techniques.iter().filter(|t| t.models(light.kind())) {
            for (i, &(backend, ctx)) in contexts.iter().enumerate() {
                let label = format!(
                    "{name} as seen {} {} {RESOLUTION} {backend:?}",
                    t.name(),
                    t.variant()
                );
                let gpu = match ctx {
                    Context::Gpu(g) => Some(g),
                    Context::Cpu(_) => None,
                };
                let v = match t
                    .generate_in(ctx, &scene.geometry, light, &scene.views, RESOLUTION)
                    .and_then(|m| m.evaluate(gpu, &scene.receivers()))
                {
                    Ok(v) => v,
                    Err(e) => {
                        skip(label, &e);
                        continue;
                    }
                };
                if i == 0 && !pictured.contains(&t.name()) {
                    pictured.push(t.name());
                    tiles.push(picture(&scene, &v));
                }
                let a = artefacts(&scene, &v);
                runs.push(SeenRun {
                    scene: name.clone(),
                    technique: t.name().to_string(),
                    variant: t.variant(),
                    backend: format!("{backend:?}").to_lowercase(),
                    resolution: RESOLUTION,
                    receivers: a.receivers,
                    darkened: a.darkened,
                    false_umbra_per_million: a.per_million(a.false_umbra),
                    leaks_per_million: a.per_million(a.leaks),
                    object_leaks_per_million: a.per_million(a.object_leaks),
                    reference_ms: scene.reference_ms,
                });
            }
        }
        write_grid(&opts.out.join(picture_file(&name)), &tiles)?;
    }
    Ok(runs)
}

/// `tiles` (all of one size) two to a row, as PNG.
fn write_grid(path: &std::path::Path, tiles: &[image::RgbImage]) -> Result<()> {
    let (w, h) = tiles.first().map_or((1, 1), |t| t.dimensions());
    let rows = tiles.len().div_ceil(2) as u32;
    let mut grid = image::RgbImage::new(2 * w, rows * h);
    for (i, t) in tiles.iter().enumerate() {
        let (x, y) = ((i as u32 % 2) * w, (i as u32 / 2) * h);
        image::imageops::replace(&mut grid, t, x as i64, y as i64);
    }
    grid.save(path)
        .map_err(|e| crate::error::HarnessError::write(path, e))
}
