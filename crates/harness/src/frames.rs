//! The frame as a whole over a camera path (`harness frames`): the lamps of the night
//! street or of the room ([`soft_shadow_reference::scenes::lamps`]) sharing one frame budget,
//! each frame's measured time against the budget
//! and the picks' prediction, and every lamp's image error against the ray-traced reference,
//! beside the error it would have with no shadow at all and the error of the frame's summed
//! lighting.
//!
//! A lamp's image error weighs each receiver by the lamp's unshadowed irradiance there over its
//! largest in the frame ([`crate::metrics::image_rms_255`], the report's image error); the
//! frame's sums every lamp's `intensity x E0 x V` per receiver and weighs by the largest sum.

use crate::error::Result;
use crate::metrics::image_rms_255;
use serde::{Deserialize, Serialize};
use shadow_frame::scene::LightSource;
use shadow_frame::{FramePipeline, FrameReceivers, LightState, ResolvedTechnique, ShadowConfig};
use soft_shadow_reference::ground_truth::irradiance::irradiance;
use soft_shadow_reference::ground_truth::{GroundTruthSettings, RayTracer};
use soft_shadow_reference::scenes::lamps::{Lamps, room, street};
use std::fmt::Write as _;

/// One lamp in one frame.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct LampFrame {
    /// The lamp's kind.
    pub kind: String,
    /// Its pick (`name variant side²`), or why it casts no shadow.
    pub pick: String,
    /// Its part of the frame's light, in `[0, 1]`.
    pub contribution: f64,
    /// Its image error against the reference, 1/255.
    pub image_255: f64,
    /// The image error `V` = 1 would have, 1/255.
    pub no_shadow_255: f64,
}

/// One frame of the path.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct FrameMeasure {
    /// Measured milliseconds of the frame pipeline's run (wall time, every system).
    pub ms: f64,
    /// Of [`FrameMeasure::ms`], the pipeline's core sets (tracking, sharing the budget,
    /// staleness): what the frame costs beyond its lamps' techniques.
    pub core_ms: f64,
    /// The picks' predicted milliseconds for a frame where every lamp makes its maps.
    pub predicted_ms: f64,
    /// Maps made in the frame.
    pub maps_generated: usize,
    /// Every lamp.
    pub lamps: Vec<LampFrame>,
    /// The image error of the frame's summed lighting, 1/255.
    pub image_255: f64,
    /// The same with no shadow at all, 1/255.
    pub no_shadow_255: f64,
}

/// Walks the camera of `walked` by `step` metres a frame for `frames` frames (the first frame
/// where it stands), runs `pipeline` on each and measures it against the reference traced with
/// `settings`.
pub fn walk(
    walked: &mut Lamps,
    pipeline: &mut FramePipeline,
    frames: u32,
    step: f32,
    settings: &GroundTruthSettings,
) -> Result<Vec<FrameMeasure>> {
    let casters = walked.scene.geometry().casters;
    let truth = RayTracer::new(&casters);
    let mut out = Vec::new();
    for f in 0..frames {
        if f > 0 {
            walked.walk(step);
        }
        let start = std::time::Instant::now();
        let stats = pipeline.run(&mut walked.scene.world);
        let ms = start.elapsed().as_secs_f64() * 1e3;
        let world = &walked.scene.world;
        let frame = world.resource::<FrameReceivers>().clone();
        let n = frame.positions.len();
        let (mut lit, mut shadowed, mut reference) = (vec![0.0f32; n], vec![0.0; n], vec![0.0; n]);
        let mut lamps = Vec::new();
        for &e in &walked.lamps {
            let light = world.get::<LightSource>(e).expect("a lamp").0;
            let config = world.get::<ShadowConfig>(e).expect("a lamp's config");
            let state = world.get::<LightState>(e).expect("a lamp's state");
            let e0: Vec<f32> = (0..n)
                .map(|i| irradiance(&light, frame.positions[i], frame.normals[i]))
                .collect();
            let (c, r) = shadow_frame::influence(&light, config.range);
            let inside: Vec<usize> = (0..n)
                .filter(|&i| e0[i] > 0.0 && frame.positions[i].distance_squared(c) <= r * r)
                .collect();
            let pos: Vec<_> = inside.iter().map(|&i| frame.positions[i]).collect();
            let nor: Vec<_> = inside.iter().map(|&i| frame.normals[i]).collect();
            let refs = truth.references(&light, &pos, &nor, settings);
            let v = |i: usize| state.visibility.get(i).copied().unwrap_or(1.0);
            let max = inside.iter().map(|&i| e0[i]).fold(0.0f32, f32::max);
            let (mut got, mut want, mut w) = (Vec::new(), Vec::new(), Vec::new());
            for (&i, r) in inside.iter().zip(&refs) {
                let Some(r) = r else { continue };
                got.push(v(i));
                want.push(r.visibility);
                w.push(e0[i] / max);
                let k = config.intensity * e0[i];
                lit[i] += k;
                shadowed[i] += k * v(i);
                reference[i] += k * r.visibility;
            }
            let ones = vec![1.0; want.len()];
            let waited =
                state.maps.is_none() && stats.lights.iter().any(|l| l.light == e && l.waited);
            let pick = match (world.get::<ResolvedTechnique>(e), &state.error) {
                // Its maps wait a frame (`shadow_frame::deadline`): no shadow in this one.
                (Some(r), Some(why)) if waited => format!(
                    "none this frame: {} {} {}², {why}",
                    r.technique.name(),
                    r.technique.variant(),
                    r.resolution
                ),
                (Some(r), Some(why)) => format!(
                    "{} {} {}², failed: {why}",
                    r.technique.name(),
                    r.technique.variant(),
                    r.resolution
                ),
                (Some(r), None) => format!(
                    "{} {} {}²",
                    r.technique.name(),
                    r.technique.variant(),
                    r.resolution
                ),
                (None, Some(why)) => format!("none: {why}"),
                (None, None) => "none: lights nothing in view".into(),
            };
            lamps.push(LampFrame {
                kind: light.kind().name().into(),
                pick,
                contribution: state.share.map_or(0.0, |s| s.contribution),
                image_255: image_rms_255(&got, &want, &w),
                no_shadow_255: image_rms_255(&ones, &want, &w),
            });
        }
        let max = lit
            .iter()
            .copied()
            .fold(0.0f32, f32::max)
            .max(f32::MIN_POSITIVE);
        let weights = vec![1.0; n];
        let scale = |x: &[f32]| x.iter().map(|y| y / max).collect::<Vec<f32>>();
        out.push(FrameMeasure {
            ms,
            core_ms: stats.core.total_ms(),
            predicted_ms: stats.predicted_ms(),
            maps_generated: stats.maps_generated,
            image_255: image_rms_255(&scale(&shadowed), &scale(&reference), &weights),
            no_shadow_255: image_rms_255(&scale(&lit), &scale(&reference), &weights),
            lamps,
        });
    }
    Ok(out)
}

/// The measurement as Markdown: one line per frame, then every lamp of the first frame and of
/// the last.
pub fn markdown(frames: &[FrameMeasure], budget_ms: f64) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "| frame | measured ms | of which the pipeline's core | predicted ms (before margins) | budget ms | maps made | frame image error | with no shadow |\n|---:|---:|---:|---:|---:|---:|---:|---:|"
    );
    for (k, f) in frames.iter().enumerate() {
        let _ = writeln!(
            s,
            "| {k} | {:.2} | {:.2} | {:.2} | {budget_ms} | {} | {:.2} | {:.2} |",
            f.ms, f.core_ms, f.predicted_ms, f.maps_generated, f.image_255, f.no_shadow_255
        );
    }
    let mut later: Vec<f64> = frames.iter().skip(1).map(|f| f.ms).collect();
    later.sort_by(f64::total_cmp);
    if let Some(median) = later.get(later.len() / 2) {
        let _ = writeln!(
            s,
            "\nMedian frame after the first (which allocates the maps): {median:.2} ms."
        );
    }
    if let (Some(first), Some(last)) = (frames.first(), frames.last()) {
        let _ = writeln!(
            s,
            "\nEvery lamp in the first frame (the profile's predictions alone) and in the last \
             (what the frames measured calibrating them, [`shadow_frame::Calibration`], and each \
             lamp's missing shadow measured from its own `V`).\n\n\
             | lamp | kind | part of the light (last frame) | first frame's pick | image error | \
             last frame's pick | image error | with no shadow (last frame) |\n\
             |---:|---|---:|---|---:|---|---:|---:|"
        );
        for (i, (a, b)) in first.lamps.iter().zip(&last.lamps).enumerate() {
            let _ = writeln!(
                s,
                "| {i} | {} | {:.1}% | {} | {:.2} | {} | {:.2} | {:.2} |",
                b.kind,
                100.0 * b.contribution,
                a.pick,
                a.image_255,
                b.pick,
                b.image_255,
                b.no_shadow_255
            );
        }
    }
    s
}

/// The scenes `harness frames` walks through.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FramesScene {
    /// `night-street` ([`street::street`]), with any number of lamps.
    Street,
    /// `room-lamps` ([`room::room`]): three lamps.
    Room,
}

impl FramesScene {
    /// Both, in [`soft_shadow_reference::scenes::lamps::LAMP_SCENES`]' order.
    pub const ALL: [FramesScene; 2] = [FramesScene::Street, FramesScene::Room];

    /// Its name in [`soft_shadow_reference::scenes::lamps::LAMP_SCENES`].
    pub fn name(self) -> &'static str {
        match self {
            FramesScene::Street => "night-street",
            FramesScene::Room => "room-lamps",
        }
    }

    /// The scene called `name`, if one is.
    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|s| s.name() == name)
    }

    /// The walk the report measures it over: its frame budget (ms) and the metres the camera
    /// walks a frame (the street's 16 ms and 0.5 m; the room's 33 ms and 0.25 m, a room being
    /// smaller and its three lamps' shadows dearer).
    pub fn walk(self) -> (f64, f32) {
        match self {
            FramesScene::Street => (16.0, 0.5),
            FramesScene::Room => (33.0, 0.25),
        }
    }
}

/// One walk measured: the scene, how it was walked, and every frame.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct FramesRun {
    /// The scene's name ([`FramesScene::name`]).
    pub scene: String,
    /// What the scene is, for titles.
    pub title: String,
    /// Its lamps.
    pub lamps: usize,
    /// The frame budget, milliseconds.
    pub budget_ms: f64,
    /// Metres the camera walked a frame.
    pub step: f32,
    /// The receivers' G-buffer, width and height.
    pub size: (u32, u32),
    /// Every frame, the first where the camera stands.
    pub frames: Vec<FrameMeasure>,
}

impl FramesRun {
    /// The `harness frames` command that measures it again.
    pub fn command(&self) -> String {
        let scene = match FramesScene::from_name(&self.scene) {
            Some(FramesScene::Street) => format!("--lamps {}", self.lamps),
            _ => format!("--scene {}", self.scene),
        };
        format!(
            "harness frames {scene} --budget-ms {} --frames {} --step {} --size {}x{}",
            self.budget_ms,
            self.frames.len(),
            self.step,
            self.size.0,
            self.size.1
        )
    }

    /// Frames measured over the budget.
    pub fn over_budget(&self) -> usize {
        self.frames.iter().filter(|f| f.ms > self.budget_ms).count()
    }

    /// The walk as a Markdown document: a title, the command, the tables ([`markdown`]).
    pub fn document(&self) -> String {
        let title = &self.title;
        format!(
            "# {}{}, {} lamps, one {} ms frame budget\n\n`{}` (CPU). Image errors in 1/255 \
             against the reference (8² strata x 2 replicates a receiver).\n\n{}",
            title[..1].to_uppercase(),
            &title[1..],
            self.lamps,
            self.budget_ms,
            self.command(),
            markdown(&self.frames, self.budget_ms)
        )
    }
}

/// `scene` (the street with `lamps` lamps, 16 when `None`; the room with its three) under a
/// `budget_ms` frame budget, receivers from a `width x height` G-buffer, walked `frames` frames
/// of `step` metres by a fresh pipeline with every technique, measured against the reference
/// (8² strata x 2 replicates a receiver). Out-of-range arguments are
/// [`crate::error::HarnessError::Usage`], named as `harness frames` takes them.
pub fn measure(
    scene: FramesScene,
    lamps: Option<usize>,
    budget_ms: f64,
    frames: u32,
    step: f32,
    (w, h): (u32, u32),
) -> Result<FramesRun> {
    use crate::error::HarnessError::Usage;
    let bad = |what: String| Err(Usage(what));
    let lamps = match (scene, lamps) {
        (FramesScene::Street, n) => n.unwrap_or(16),
        (FramesScene::Room, None | Some(3)) => 3,
        (FramesScene::Room, Some(n)) => {
            return bad(format!("--lamps: the room has 3 lamps, got {n}"));
        }
    };
    if !(1..=256).contains(&lamps) {
        return bad(format!("--lamps must be in 1..=256, got {lamps}"));
    }
    if !(budget_ms.is_finite() && budget_ms > 0.0) {
        return bad(format!(
            "--budget-ms must be a positive number of milliseconds, got {budget_ms}"
        ));
    }
    if !(1..=1000).contains(&frames) {
        return bad(format!("--frames must be in 1..=1000, got {frames}"));
    }
    if !step.is_finite() || step.abs() > 100.0 {
        return bad(format!(
            "--step must be a number of metres within 100, got {step}"
        ));
    }
    if !((1..=4096).contains(&w) && (1..=4096).contains(&h)) {
        return bad(format!(
            "--size must be WIDTHxHEIGHT, each in 1..=4096 (such as 320x180), got {w}x{h}"
        ));
    }
    let mut lit = match scene {
        FramesScene::Street => street::street(lamps, w, h, budget_ms)?,
        FramesScene::Room => room::room(w, h, budget_ms)?,
    };
    let mut pipeline = crate::animated::pipeline();
    let settings = GroundTruthSettings {
        strata_side: 8,
        replicates: 2,
        ..Default::default()
    };
    let measured = walk(&mut lit, &mut pipeline, frames, step, &settings)?;
    Ok(FramesRun {
        scene: scene.name().into(),
        title: lit.title.clone(),
        lamps,
        budget_ms,
        step,
        size: (w, h),
        frames: measured,
    })
}

/// `harness frames`: [`measure`] with a `size` given as `WxH`, written as Markdown
/// ([`FramesRun::document`]) to `out`; returns the line to print.
#[allow(clippy::too_many_arguments)]
pub fn run(
    scene: FramesScene,
    lamps: Option<usize>,
    budget_ms: f64,
    frames: u32,
    step: f32,
    size: &str,
    out: &std::path::Path,
) -> Result<String> {
    let parsed = size
        .split_once('x')
        .and_then(|(w, h)| Some((w.parse::<u32>().ok()?, h.parse::<u32>().ok()?)));
    let Some((w, h)) = parsed else {
        return Err(crate::error::HarnessError::Usage(format!(
            "--size must be WIDTHxHEIGHT, each in 1..=4096 (such as 320x180), got {size:?}"
        )));
    };
    let run = measure(scene, lamps, budget_ms, frames, step, (w, h))?;
    if let Some(dir) = out.parent().filter(|d| !d.as_os_str().is_empty()) {
        crate::files::create_dir(dir)?;
    }
    crate::files::write_text(out, &run.document())?;
    Ok(format!(
        "wrote {} ({frames} frames, {} over the {budget_ms} ms budget)",
        out.display(),
        run.over_budget()
    ))
}
