//! The report's "as seen" section: every technique's `V` over the frame a person looks at
//! ([`crate::as_seen`]: 1280 x 720, maps at 1024²), with the artefacts counted there.

use super::json::SeenRun;
use super::options::ReportOptions;
use crate::as_seen::{artefacts, frame};
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

/// Every technique of `techniques` that models the scene's light, on `backends`, over the frame
/// of each scene of [`scene_names`]; a configuration that fails is recorded by `skip`.
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
        for t in techniques.iter().filter(|t| t.models(light.kind())) {
            for &(backend, ctx) in contexts {
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
    }
    Ok(runs)
}
