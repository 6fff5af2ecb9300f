//! The scenes of many lamps in the report ([`soft_shadow_reference::scenes::lamps`]): each one
//! selected is walked over its camera path by the frame pipeline under one frame budget
//! ([`crate::frames::measure`], the budget and step of [`FramesScene::walk`], 8 frames), every
//! frame's time against the budget and every lamp's image error against the reference,
//! written to `frames-<scene>.md` and to `report.json`'s `frames`.

use super::options::ReportOptions;
use crate::error::Result;
use crate::frames::{FramesRun, FramesScene, measure};

/// Frames of each walk.
pub const FRAMES: u32 = 8;

/// The receivers' G-buffer of a walk: 320 x 180, with `--quick` 160 x 90.
pub fn size(opts: &ReportOptions) -> (u32, u32) {
    if opts.quick { (160, 90) } else { (320, 180) }
}

/// The scenes of lamps the report walks: those `--scenes` names (each once), both where it
/// names none (none with `--scene-file` alone).
pub fn selected(opts: &ReportOptions) -> Vec<FramesScene> {
    match &opts.scenes {
        Some(names) => FramesScene::ALL
            .into_iter()
            .filter(|s| names.iter().any(|n| n == s.name()))
            .collect(),
        None if opts.scene_files.is_empty() => FramesScene::ALL.to_vec(),
        None => Vec::new(),
    }
}

/// The file a scene's walk is written to in the output folder: `frames-<scene>.md`.
pub fn file(scene: &str) -> String {
    format!("frames-{}.md", super::file_stem(scene))
}

/// Walks every scene of `scenes` on the CPU (whatever `--techniques`, `--resolutions`,
/// `--size` and `--backend` say: the frame budget picks every lamp's configuration) and writes
/// each one's document into `opts.out`. A walk that fails is left out and its reason pushed to
/// `skipped`; a document that cannot be written is the report's error.
pub fn measure_all(
    opts: &ReportOptions,
    scenes: &[FramesScene],
    skipped: &mut Vec<String>,
) -> Result<Vec<FramesRun>> {
    let mut runs = Vec::new();
    for &scene in scenes {
        let (budget_ms, step) = scene.walk();
        match measure(scene, None, budget_ms, FRAMES, step, size(opts)) {
            Ok(run) => {
                crate::files::write_text(&opts.out.join(file(&run.scene)), &run.document())?;
                runs.push(run);
            }
            Err(e) => {
                let line = format!("skipped the walk of {}: {e}", scene.name());
                eprintln!("{line}");
                skipped.push(line);
            }
        }
    }
    Ok(runs)
}
