//! The `report` subcommand: every technique on every scene against the ground truth, with times.

pub mod cost;
pub mod flicker;
pub mod html;
pub mod images;
pub mod json;
pub mod lamps;
pub mod markdown;
pub mod measure;
pub mod options;
pub mod pareto;
pub mod progress;
pub mod seen;
pub mod stability;
pub mod summary;

use crate::error::{HarnessError, Result};
use crate::files::{create_dir, write_text};
use crate::metrics::errors;
use crate::setup::PreparedScene;
use json::{Machine, ReferenceInfo, Report, Run};
pub use options::{BackendChoice, MemoryBudgets, ReportOptions, all_techniques};
use progress::Progress;
use soft_shadow_core::{
    Backend, Context, CpuContext, DynTechnique, GpuContext, ShadowError, Technique,
};
use soft_shadow_reference::ground_truth::GroundTruthSettings;
use soft_shadow_reference::scenes::{SceneSpec, catalogue, scene_file};
use std::collections::HashSet;

fn cpu_name() -> String {
    std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|s| {
            s.lines()
                .find(|l| l.starts_with("model name"))
                .and_then(|l| l.split(':').nth(1))
                .map(|s| s.trim().to_string())
        })
        .unwrap_or_else(|| std::env::consts::ARCH.to_string())
}

/// `report --list`: the built-in scenes with what each tests, then every technique with its
/// variants as `--techniques` takes them (`technique` or `technique:variant`).
pub fn listing(quick: bool) -> String {
    use std::fmt::Write as _;
    let mut s = String::from("scenes (--scenes):\n");
    for name in catalogue::SCENE_NAMES {
        let what = catalogue::build(name).map_or_else(|e| e.to_string(), |spec| spec.description);
        let _ = writeln!(s, "  {name:18} {what}");
    }
    s.push_str("scenes of the as-seen frames only (--scenes also runs them as the others):\n");
    for name in catalogue::AS_SEEN_NAMES {
        let what = catalogue::build(name).map_or_else(|e| e.to_string(), |spec| spec.description);
        let _ = writeln!(s, "  {name:18} {what}");
    }
    s.push_str(
        "scenes of many lamps under one frame budget, walked by the frame pipeline (--scenes; \
         harness frames --scene; viewer --scene):\n",
    );
    for (name, what) in soft_shadow_reference::scenes::lamps::LAMP_SCENES {
        let _ = writeln!(s, "  {name:18} {what}");
    }
    s.push_str("techniques (--techniques technique or technique:variant):\n");
    let mut rows: Vec<(String, Vec<String>)> = Vec::new();
    for t in all_techniques(quick) {
        match rows.iter_mut().find(|r| r.0 == t.name()) {
            Some(r) => r.1.push(t.variant()),
            None => rows.push((t.name().to_string(), vec![t.variant()])),
        }
    }
    for (name, variants) in rows {
        let _ = writeln!(s, "  {name:18} {}", variants.join(", "));
    }
    s
}

fn select_scenes(opts: &ReportOptions) -> Result<Vec<SceneSpec>> {
    let mut specs = Vec::new();
    let names: Vec<String> = match &opts.scenes {
        Some(v) => v.clone(),
        None if opts.scene_files.is_empty() => catalogue::SCENE_NAMES
            .iter()
            .map(|s| s.to_string())
            .collect(),
        None => Vec::new(),
    };
    for n in names {
        // The scenes of many lamps are walked by the frame pipeline ([`lamps`]).
        if crate::frames::FramesScene::from_name(&n).is_none() {
            specs.push(catalogue::build(&n)?);
        }
    }
    for f in &opts.scene_files {
        specs.push(scene_file::load(f)?);
    }
    Ok(specs)
}

/// The file name a scene's outputs use: its name with every character other than ASCII letters,
/// digits, `-`, `_`, `@` and inner `.` replaced by `_` (so no scene name, from a file or
/// otherwise, can reach outside the output folder); `scene` if nothing is left.
pub fn file_stem(name: &str) -> String {
    let s: String = name
        .chars()
        .enumerate()
        .map(|(i, c)| match c {
            'a'..='z' | 'A'..='Z' | '0'..='9' | '-' | '_' | '@' => c,
            '.' if i > 0 => c,
            _ => '_',
        })
        .collect();
    if s.is_empty() { "scene".into() } else { s }
}

/// One scene of the run and the techniques (indices) it runs: all of them, or, for a hard case
/// recast under another light ([`SceneSpec::relit`]), those that do not model its own light.
struct Job {
    spec: SceneSpec,
    techniques: Vec<usize>,
    relit_from: Option<String>,
}

fn jobs(specs: Vec<SceneSpec>, techniques: &[Technique]) -> Result<Vec<Job>> {
    let mut out = Vec::new();
    for spec in specs {
        let mut relit: Vec<Job> = Vec::new();
        if spec.hard_case {
            let bounds = spec.casting_bounds()?;
            for (i, t) in techniques.iter().enumerate() {
                let Some(r) = spec.relit(&bounds, |k| t.models(k)) else {
                    continue;
                };
                match relit.iter_mut().find(|j| j.spec.name == r.name) {
                    Some(j) => j.techniques.push(i),
                    None => relit.push(Job {
                        spec: r,
                        techniques: vec![i],
                        relit_from: Some(spec.name.clone()),
                    }),
                }
            }
        }
        out.push(Job {
            spec,
            techniques: (0..techniques.len()).collect(),
            relit_from: None,
        });
        out.extend(relit);
    }
    Ok(out)
}

/// What every scene of one report shares.
struct Runner<'a> {
    opts: &'a ReportOptions,
    size: u32,
    settings: GroundTruthSettings,
    resolutions: Vec<u32>,
    techniques: Vec<Technique>,
    backends: Vec<Backend>,
    cpu: CpuContext,
    gpu: Option<GpuContext>,
    bar: Progress,
    /// Techniques already warmed up on the GPU.
    warmed: HashSet<usize>,
    /// Why configurations were skipped (printed as they happen, and in the error when nothing ran).
    skipped: Vec<String>,
}

/// A strip column: label, resolution, backend, `V`.
type StripColumn = (String, u32, Backend, Vec<f32>);

impl Runner<'_> {
    /// The context `backend` runs in.
    fn context(&self, backend: Backend) -> std::result::Result<Context<'_>, ShadowError> {
        match (backend, &self.gpu) {
            (Backend::Cpu, _) => Ok(Context::Cpu(&self.cpu)),
            (Backend::Gpu, Some(g)) => Ok(Context::Gpu(g)),
            (Backend::Gpu, None) => Err(ShadowError::NoAdapter(
                "the GPU backend was asked for without a GPU context".into(),
            )),
        }
    }

    fn runs_per_scene(&self, job: &Job) -> u64 {
        let flicker = if flicker::SCENES.contains(&job.spec.name.as_str()) {
            job.techniques.len() * self.backends.len()
        } else {
            0
        };
        1 + (job.techniques.len() * self.resolutions.len() * self.backends.len() + flicker) as u64
    }

    /// Measures every technique of `job` and writes its strip, Pareto chart and EXR data.
    fn scene(&mut self, job: Job, report: &mut Report) -> Result<()> {
        let name = job.spec.name.clone();
        self.bar.set_message(format!("{name}: reference"));
        let p = PreparedScene::new(job.spec, self.size, self.settings)?;
        refuse_uncovered(&name, &p)?;
        let reference = p.reference_v();
        // The catalogue's `acne` is unshadowed by design; the warning is for users' scenes.
        let builtin = catalogue::SCENE_NAMES.contains(&name.split('@').next().unwrap_or(&name));
        if let Some(w) = no_shadow_warning(&name, &reference).filter(|_| !builtin) {
            self.bar.suspend(|| eprintln!("{w}"));
        }
        let penumbra = reference
            .iter()
            .filter(|&&r| r > crate::metrics::PENUMBRA_LO && r < crate::metrics::PENUMBRA_HI)
            .count();
        report.references.push(ReferenceInfo {
            scene: name.clone(),
            light: p.spec.light.kind().name().into(),
            relit_from: job.relit_from.clone(),
            method: "monte-carlo".into(),
            samples_per_pixel: self.settings.samples_per_pixel(),
            std_error_255: p.std_error_255(),
            max_std_error_255: p.max_std_error_255(),
            receivers: p.positions.len(),
            caster_triangles: p.geometry.casters.len(),
            covered_receivers: shadow_frame::SceneSize::with_views(
                &p.geometry,
                &p.spec.light,
                &p.positions,
                &p.views,
            )
            .covered,
            unlit_receivers: p.unlit_pixels.len(),
            light_views: p.views.len(),
            view_kind: p.views.kind_name().into(),
            penumbra_receivers: penumbra,
            time_ms: p.reference_ms,
        });
        self.bar.inc();
        let exr_dir = self.opts.out.join("exr").join(file_stem(&name));
        create_dir(&exr_dir)?;
        images::write_scene_exr(&exr_dir, self.size, &p)?;
        let mut strip: Vec<StripColumn> = Vec::new();
        for &ti in &job.techniques {
            for ri in 0..self.resolutions.len() {
                for bi in 0..self.backends.len() {
                    let (resolution, backend) = (self.resolutions[ri], self.backends[bi]);
                    if let Some(run) =
                        self.run(ti, backend, resolution, &p, &reference, &mut strip)?
                    {
                        report.runs.push(run);
                    }
                    self.bar.inc();
                }
            }
        }
        if flicker::SCENES.contains(&name.as_str()) {
            self.flicker(&job.techniques, &p, &mut report.runs)?;
        }
        self.write_strip(&name, &p, &reference, &strip, report)
    }

    /// One configuration; `None` (after a printed line) when the technique cannot run it.
    fn run(
        &mut self,
        ti: usize,
        backend: Backend,
        resolution: u32,
        p: &PreparedScene,
        reference: &[f32],
        strip: &mut Vec<StripColumn>,
    ) -> Result<Option<Run>> {
        let t = self.techniques[ti].as_ref();
        let name = &p.spec.name;
        self.bar.set_message(format!(
            "{name}: {} {} {} {resolution}",
            t.name(),
            t.variant(),
            backend.name()
        ));
        let warm_up = backend == Backend::Gpu && self.warmed.insert(ti);
        let reps = if self.opts.quick {
            measure::QUICK_MAX_REPS
        } else {
            measure::MAX_REPS
        };
        // At the cost table's resolution the hard shadow map is timed just before every other
        // configuration: the denominator of its `x hard` ratios.
        let beside = (resolution == self.resolutions.iter().copied().max().unwrap_or(resolution)
            && t.name() != cost::HARD)
            .then(|| self.techniques.iter().find(|h| h.name() == cost::HARD))
            .flatten()
            .map(|h| h.as_ref());
        let ctx = self.context(backend)?;
        let m = match measure::measure(t, ctx, p, resolution, reps, warm_up, beside) {
            Ok(m) => m,
            // A light the technique does not model, a resolution or memory need over the
            // backend's limits, or a GPU fault (out of memory, a lost device) on the GPU row:
            // that configuration is skipped and the others go on.
            Err(e)
                if matches!(
                    e,
                    ShadowError::InvalidResolution { .. }
                        | ShadowError::UnsupportedLight { .. }
                        | ShadowError::OverBudget { .. }
                ) || (backend == Backend::Gpu && matches!(e, ShadowError::Gpu(_))) =>
            {
                skip(
                    &self.bar,
                    &mut self.skipped,
                    format!(
                        "{name} {} {} {} {resolution}",
                        t.name(),
                        t.variant(),
                        backend.name()
                    ),
                    &e,
                );
                return Ok(None);
            }
            Err(e) => return Err(e.into()),
        };
        let run = Run {
            scene: name.clone(),
            technique: t.name().to_string(),
            variant: t.variant(),
            backend: backend.name().to_string(),
            resolution,
            generate_ms: m.generate_ms,
            evaluate_ms: m.evaluate_ms,
            hard_generate_ms: m.beside_ms.map(|b| b.0),
            hard_evaluate_ms: m.beside_ms.map(|b| b.1),
            errors: errors(&m.v, reference, &p.shading),
            flicker_255: None,
        };
        let file = self
            .opts
            .out
            .join("exr")
            .join(file_stem(name))
            .join(format!(
                "{}-{}-{}-{resolution}.exr",
                run.technique, run.variant, run.backend
            ));
        images::write_exr_scalar(
            &file,
            self.size,
            &images::scatter(self.size, &p.pixels, &m.v),
        )?;
        // The strip shows each variant once: its highest resolution, CPU on ties.
        let label = format!("{}/{}", run.technique, run.variant);
        match strip.iter_mut().find(|s| s.0 == label) {
            Some(s) if (resolution, backend == Backend::Cpu) > (s.1, s.2 == Backend::Cpu) => {
                *s = (label, resolution, backend, m.v)
            }
            Some(_) => {}
            None => strip.push((label, resolution, backend, m.v)),
        }
        Ok(Some(run))
    }

    /// `flicker_255` of every technique and backend at the flicker resolution, stored on the
    /// matching runs.
    fn flicker(&mut self, techniques: &[usize], p: &PreparedScene, runs: &mut [Run]) -> Result<()> {
        let Some(resolution) = self.opts.flicker_resolution() else {
            return Ok(());
        };
        self.bar
            .set_message(format!("{}: flicker references", p.spec.name));
        let frames = if self.opts.quick {
            flicker::QUICK_FRAMES
        } else {
            flicker::FRAMES
        };
        let refs = flicker::references(p, frames);
        for &ti in techniques {
            let t = self.techniques[ti].as_ref();
            for &backend in &self.backends {
                self.bar.set_message(format!(
                    "{}: flicker {} {} {}",
                    p.spec.name,
                    t.name(),
                    t.variant(),
                    backend.name()
                ));
                let run = runs.iter_mut().find(|r| {
                    r.scene == p.spec.name
                        && r.technique == t.name()
                        && r.variant == t.variant()
                        && r.backend == backend.name()
                        && r.resolution == resolution
                });
                if let Some(run) = run {
                    run.flicker_255 = Some(flicker::measure(
                        t,
                        self.context(backend)?,
                        p,
                        resolution,
                        &refs,
                    )?);
                }
                self.bar.inc();
            }
        }
        Ok(())
    }

    fn write_strip(
        &self,
        name: &str,
        p: &PreparedScene,
        reference: &[f32],
        strip: &[StripColumn],
        report: &mut Report,
    ) -> Result<()> {
        let out = &self.opts.out;
        let reference_img = images::scatter(self.size, &p.pixels, reference);
        let weight_img = images::scatter(self.size, &p.pixels, &p.shading.weight);
        let runs_img: Vec<Vec<Option<f32>>> = strip
            .iter()
            .map(|s| images::scatter(self.size, &p.pixels, &s.3))
            .collect();
        images::write_strip(
            &out.join(format!("{}.png", file_stem(name))),
            self.size,
            &reference_img,
            &weight_img,
            &runs_img,
            &p.unlit_pixels,
        )?;
        let scene_runs: Vec<Run> = report
            .runs
            .iter()
            .filter(|r| r.scene == name)
            .cloned()
            .collect();
        pareto::draw(
            &out.join(format!("pareto-{}.png", file_stem(name))),
            &format!("{name}: error vs time"),
            &scene_runs,
        )?;
        let mut columns = vec![format!(
            "reference (monte-carlo, {} spp where not proven lit)",
            self.settings.samples_per_pixel()
        )];
        columns.extend(
            strip
                .iter()
                .map(|s| format!("{} ({} {})", s.0, s.2.name(), s.1)),
        );
        let tiles = strip
            .iter()
            .map(|(label, resolution, backend, _)| {
                let (technique, variant) = label.split_once('/').unwrap_or((label, ""));
                let run = scene_runs.iter().find(|r| {
                    r.technique == technique
                        && r.variant == variant
                        && r.resolution == *resolution
                        && r.backend == backend.name()
                });
                json::StripTile {
                    technique: technique.into(),
                    variant: variant.into(),
                    backend: backend.name().into(),
                    resolution: *resolution,
                    rms_255: run.map_or(f64::NAN, |r| r.errors.rms_255),
                    image_rms_255: run.map_or(f64::NAN, |r| r.errors.image_rms_255),
                }
            })
            .collect();
        report.strips.push(json::Strip {
            scene: name.to_string(),
            file: format!("{}.png", file_stem(name)),
            columns,
            size: self.size,
            tiles,
        });
        Ok(())
    }
}

fn select_techniques(opts: &ReportOptions) -> Result<Vec<Technique>> {
    let mut techniques = opts.registry.techniques(opts.tier());
    if let Some(names) = &opts.techniques {
        // `technique` selects every variant, `technique:variant` one.
        let selects = |n: &str, t: &dyn DynTechnique| match n.split_once(':') {
            Some((name, variant)) => t.name() == name && t.variant() == variant,
            None => t.name() == n,
        };
        for n in names {
            if !techniques.iter().any(|t| selects(n, t.as_ref())) {
                let mut known: Vec<String> = Vec::new();
                for t in &techniques {
                    if !known.iter().any(|k| k == t.name()) {
                        known.push(t.name().to_string());
                    }
                }
                let variants: Vec<String> = techniques
                    .iter()
                    .map(|t| format!("{}:{}", t.name(), t.variant()))
                    .collect();
                return Err(ShadowError::InvalidParameter(format!(
                    "unknown technique {n:?}; techniques: {}; variants: {}",
                    known.join(", "),
                    variants.join(", ")
                ))
                .into());
            }
        }
        techniques.retain(|t| names.iter().any(|n| selects(n, t.as_ref())));
    }
    Ok(techniques)
}

fn select_gpu(choice: BackendChoice) -> Result<(Option<GpuContext>, String)> {
    Ok(match choice {
        BackendChoice::Cpu => (None, "not used (--backend cpu)".to_string()),
        BackendChoice::Gpu => {
            let g = GpuContext::new()?;
            let d = g.describe();
            (Some(g), d)
        }
        BackendChoice::All => match GpuContext::new() {
            Ok(g) => {
                let d = g.describe();
                (Some(g), d)
            }
            Err(e) => {
                eprintln!("warning: {e}; running the CPU backend only");
                (None, format!("none: {e}"))
            }
        },
    })
}

/// The warning for a scene where no caster shadows any receiver the camera sees (every reference
/// `V` above 0.999): a plausible but empty report, usually a light on the wrong side or meshes
/// not marked `caster`. `None` when something is shadowed.
pub fn no_shadow_warning(scene: &str, reference: &[f32]) -> Option<String> {
    (!reference.is_empty() && reference.iter().all(|&v| v > 0.999)).then(|| {
        format!(
            "warning: {scene}: no caster shadows any receiver the camera sees (the reference is \
             lit everywhere); check the light's position or direction (a distant light's \
             `direction` points towards the light) and which meshes are casters"
        )
    })
}

/// Runs the report and writes `report.json`, `report.md`, `index.html`, PNG strips, Pareto
/// charts and EXR data into `opts.out`.
pub fn run(opts: &ReportOptions) -> Result<Report> {
    let size = opts.size();
    if size == 0 || size > 4096 {
        return Err(ShadowError::InvalidParameter(format!(
            "--size (the G-buffer side in pixels) must be in 1..=4096, got {size}"
        ))
        .into());
    }
    let settings = GroundTruthSettings::default();
    let resolutions = opts.resolutions();
    if let Some(&bad) = resolutions.iter().find(|&&r| r == 0) {
        return Err(ShadowError::InvalidResolution {
            requested: bad,
            max: soft_shadow_core::technique::MAX_CPU_RESOLUTION,
        }
        .into());
    }
    let techniques = select_techniques(opts)?;
    let (gpu, gpu_adapter) = select_gpu(opts.backend)?;
    if let (Some(g), Some(bytes)) = (&gpu, opts.memory.gpu) {
        g.set_memory_budget(bytes);
    }
    let mut backends = Vec::new();
    if opts.backend != BackendChoice::Gpu {
        backends.push(Backend::Cpu);
    }
    if gpu.is_some() {
        backends.push(Backend::Gpu);
    }
    let jobs = jobs(select_scenes(opts)?, &techniques)?;
    // Two scenes whose outputs would share a file are refused before anything runs.
    let mut stems: std::collections::HashMap<String, &str> = std::collections::HashMap::new();
    for j in &jobs {
        if let Some(other) = stems.insert(file_stem(&j.spec.name), &j.spec.name) {
            return Err(ShadowError::InvalidScene(format!(
                "scenes {other:?} and {:?} would write the same files ({})",
                j.spec.name,
                file_stem(&j.spec.name)
            ))
            .into());
        }
    }
    let seen_scenes = seen::specs(opts)?;
    create_dir(&opts.out)?;
    let mut runner = Runner {
        opts,
        size,
        settings,
        resolutions,
        techniques,
        backends,
        cpu: match opts.memory.cpu {
            Some(bytes) => CpuContext::with_memory_budget(bytes),
            None => CpuContext::new(),
        },
        gpu,
        bar: Progress::with_mode(0, false),
        warmed: HashSet::new(),
        skipped: Vec::new(),
    };
    let total: u64 = jobs.iter().map(|j| runner.runs_per_scene(j)).sum::<u64>()
        + seen::steps(
            opts,
            &seen_scenes,
            &runner.techniques,
            runner.backends.len(),
        );
    runner.bar = Progress::new(total);
    let mut report = Report {
        version: 1,
        machine: Machine {
            cpu: cpu_name(),
            threads: rayon::current_num_threads(),
            gpu_adapter,
            write_once_ms: 0.0,
        },
        references: Vec::new(),
        runs: Vec::new(),
        strips: Vec::new(),
        skipped: Vec::new(),
        as_seen: Vec::new(),
        frames: Vec::new(),
    };
    for job in jobs {
        runner.scene(job, &mut report)?;
    }
    {
        // Every backend of the runs: the CPU where it ran, the GPU where there is one.
        let contexts: Vec<(Backend, Context<'_>)> = runner
            .backends
            .iter()
            .filter_map(|&b| match b {
                Backend::Cpu => Some((b, Context::Cpu(&runner.cpu))),
                Backend::Gpu => runner.gpu.as_ref().map(|g| (b, Context::Gpu(g))),
            })
            .collect();
        report.as_seen = seen::measure(
            opts,
            seen_scenes,
            &runner.techniques,
            &contexts,
            &mut runner.bar,
            &mut runner.skipped,
        )?;
    }
    runner.bar.finish();
    report.frames = lamps::measure_all(opts, &lamps::selected(opts), &mut runner.skipped)?;
    report.skipped = runner.skipped.clone();
    // Measured after the runs, at the largest resolution one of them reached (a resolution
    // every configuration refused is never allocated).
    let largest = report.runs.iter().map(|r| r.resolution).max().unwrap_or(0);
    report.machine.write_once_ms = cost::write_once_ms(largest);
    if report.runs.is_empty() && report.frames.is_empty() {
        return Err(HarnessError::NothingRan(format!(
            "every configuration was skipped ({})",
            if runner.skipped.is_empty() {
                "no technique, resolution and backend to run".to_string()
            } else {
                runner.skipped.join("; ")
            }
        )));
    }
    pareto::draw(
        &opts.out.join("pareto.png"),
        "all scenes: mean error vs mean time",
        &pareto::scene_means(&report.runs),
    )?;
    write_text(
        &opts.out.join("report.json"),
        &serde_json::to_string_pretty(&report)
            .map_err(|e| HarnessError::write(&opts.out.join("report.json"), e))?,
    )?;
    let md = markdown::render(&report, opts.out.join("papers.html").is_file());
    write_text(&opts.out.join("report.md"), &md)?;
    write_text(
        &opts.out.join("index.html"),
        &html::render_report(&md, &report.strips),
    )?;
    Ok(report)
}

/// Refuses a scene whose views leave a caster out ([`PreparedScene::uncovered`]), naming the
/// light and (up to three of) what they leave out.
pub(crate) fn refuse_uncovered(name: &str, p: &PreparedScene) -> Result<()> {
    if p.uncovered.is_empty() {
        return Ok(());
    }
    let n = p.uncovered.len();
    let mut what = p.uncovered[..n.min(3)].join(", ");
    if n > 3 {
        what += &format!(" and {} more", n - 3);
    }
    Err(HarnessError::Uncovered {
        scene: name.to_string(),
        light: p.spec.light.kind().name().into(),
        views: p.views.kind_name().into(),
        what,
    })
}

/// Prints (on stderr, whether or not a terminal shows the bar: `println` drops the line when
/// the bar is hidden) and records why configuration `label` did not run.
fn skip(bar: &Progress, skipped: &mut Vec<String>, label: String, e: &ShadowError) {
    let line = format!("skipped {label}: {e}");
    bar.suspend(|| eprintln!("{line}"));
    skipped.push(line);
}

#[cfg(test)]
mod tests {
    use super::*;
    use soft_shadow_core::LightViews;

    /// A lamp among furniture seen through one frustum (what every light had before views
    /// were chosen for the scene) leaves casters out: the report refuses the scene, naming the
    /// scene, the light, its views and the casters, instead of measuring a missing shadow; the
    /// cube faces it plans hold every caster.
    #[test]
    fn a_scene_whose_views_leave_a_caster_out_is_refused_by_name() {
        let settings = GroundTruthSettings {
            strata_side: 2,
            replicates: 1,
            ..Default::default()
        };
        let mut p =
            PreparedScene::new(catalogue::build("room-lamp").unwrap(), 24, settings).unwrap();
        assert_eq!(p.views.kind_name(), "cube");
        assert!(p.uncovered.is_empty(), "{:?}", p.uncovered);
        assert!(refuse_uncovered("room-lamp", &p).is_ok());
        p.views = LightViews::single();
        let light = p.spec.light;
        p.uncovered = crate::setup::uncovered(&p.spec, &light, &p.geometry, &p.views, &p.positions);
        let err = refuse_uncovered("room-lamp", &p).unwrap_err().to_string();
        println!("{err}");
        for part in [
            "room-lamp:",
            "sphere light",
            "single views",
            "caster `",
            "not measured",
        ] {
            assert!(err.contains(part), "{part:?} in {err}");
        }
    }
}
