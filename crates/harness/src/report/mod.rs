//! The `report` subcommand: every technique on every scene against the ground truth, with times.

pub mod html;
pub mod images;
pub mod json;
pub mod markdown;
pub mod pareto;
pub mod summary;

use crate::baselines::ShadowMapBaseline;
use crate::ground_truth::GroundTruthSettings;
use crate::metrics::{errors, median};
use crate::scenes::{SceneSpec, catalogue, scene_file};
use crate::setup::PreparedScene;
use indicatif::{ProgressBar, ProgressStyle};
use json::{Machine, ReferenceInfo, Report, Run};
use linear_light::LinearLight;
use occlusion_slices::OcclusionSlices;
use penumbra_limit::PenumbraLimit;
use shadow_core::{Backend, DynTechnique, GpuContext, Result, ShadowError};
use shadow_width::ShadowWidth;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Which backends to run.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BackendChoice {
    /// CPU only.
    Cpu,
    /// GPU only (an error without an adapter).
    Gpu,
    /// Both; without an adapter, CPU only with a warning.
    All,
}

/// Options of `report`, as the CLI flags of the guide.
#[derive(Clone, Debug)]
pub struct ReportOptions {
    /// `--quick`: 128² G-buffer, resolution 256, fewer variants; under 2 minutes on 2 cores.
    pub quick: bool,
    /// `--out`.
    pub out: PathBuf,
    /// `--scenes` (built-in names); `None` = all.
    pub scenes: Option<Vec<String>>,
    /// `--techniques` (technique names); `None` = all.
    pub techniques: Option<Vec<String>>,
    /// `--resolutions`; `None` = 64,256,1024 (quick: 256).
    pub resolutions: Option<Vec<u32>>,
    /// `--backend`.
    pub backend: BackendChoice,
    /// `--scene-file`, repeatable.
    pub scene_files: Vec<PathBuf>,
    /// `--size`: G-buffer side; `None` = 512 (quick: 128).
    pub size: Option<u32>,
}

/// Every technique the report knows, for `--techniques`.
pub fn all_techniques(quick: bool) -> Vec<Box<dyn DynTechnique>> {
    let accumulation: &[u32] = if quick { &[16] } else { &[4, 16, 64, 256] };
    let baselines = ShadowMapBaseline::standard_set(accumulation)
        .into_iter()
        .map(|b| Box::new(b) as Box<dyn DynTechnique>);
    let shadow_width = ShadowWidth::standard_set()
        .into_iter()
        .map(|t| Box::new(t) as Box<dyn DynTechnique>);
    let penumbra_limit = PenumbraLimit::standard_set()
        .into_iter()
        .map(|t| Box::new(t) as Box<dyn DynTechnique>);
    let occlusion_slices = OcclusionSlices::standard_set()
        .into_iter()
        .map(|t| Box::new(t) as Box<dyn DynTechnique>);
    let linear_light = LinearLight::standard_set()
        .into_iter()
        .map(|t| Box::new(t) as Box<dyn DynTechnique>);
    baselines
        .chain(shadow_width)
        .chain(penumbra_limit)
        .chain(occlusion_slices)
        .chain(linear_light)
        .collect()
}

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
        specs.push(catalogue::build(&n)?);
    }
    for f in &opts.scene_files {
        specs.push(scene_file::load(f)?);
    }
    Ok(specs)
}

struct Measured {
    generate_ms: f64,
    evaluate_ms: f64,
    v: Vec<f32>,
}

fn measure(
    t: &dyn DynTechnique,
    backend: Backend,
    gpu: Option<&GpuContext>,
    p: &PreparedScene,
    res: u32,
) -> Result<Measured> {
    let light = &p.spec.light;
    if backend == Backend::Gpu {
        // Warm-up: pipelines are compiled on first use and cached per device.
        let maps = t.generate(backend, gpu, &p.geometry, light, res)?;
        t.evaluate(gpu, &maps, &p.receivers())?;
    }
    let (mut gen_t, mut eval_t) = (Vec::new(), Vec::new());
    let start = Instant::now();
    let mut v = Vec::new();
    for _ in 0..3 {
        let t0 = Instant::now();
        let maps = t.generate(backend, gpu, &p.geometry, light, res)?;
        let t1 = Instant::now();
        v = t.evaluate(gpu, &maps, &p.receivers())?;
        let t2 = Instant::now();
        gen_t.push((t1 - t0).as_secs_f64() * 1e3);
        eval_t.push((t2 - t1).as_secs_f64() * 1e3);
        if start.elapsed().as_secs_f64() > 2.0 {
            break;
        }
    }
    Ok(Measured {
        generate_ms: median(&gen_t),
        evaluate_ms: median(&eval_t),
        v,
    })
}

fn create_dir(path: &Path) -> Result<()> {
    std::fs::create_dir_all(path).map_err(|source| ShadowError::Io {
        path: path.display().to_string(),
        source,
    })
}

/// Runs the report and writes `report.json`, `report.md`, PNG strips, Pareto charts and EXR data into `opts.out`.
pub fn run(opts: &ReportOptions) -> Result<Report> {
    let quick = opts.quick;
    let size = opts.size.unwrap_or(if quick { 128 } else { 512 });
    if size == 0 || size > 4096 {
        return Err(ShadowError::InvalidResolution {
            requested: size,
            max: 4096,
        });
    }
    let settings = if quick {
        GroundTruthSettings {
            strata_side: 32,
            replicates: 4,
        }
    } else {
        GroundTruthSettings::default()
    };
    let resolutions = opts.resolutions.clone().unwrap_or(if quick {
        vec![256]
    } else {
        vec![64, 256, 1024]
    });
    if let Some(&bad) = resolutions.iter().find(|&&r| r == 0) {
        return Err(ShadowError::InvalidResolution {
            requested: bad,
            max: shadow_core::technique::MAX_CPU_RESOLUTION,
        });
    }
    let mut techniques = all_techniques(quick);
    if let Some(names) = &opts.techniques {
        for n in names {
            if !techniques.iter().any(|t| t.name() == n) {
                let known: Vec<&str> = techniques.iter().map(|t| t.name()).collect();
                return Err(ShadowError::InvalidScene(format!(
                    "unknown technique {n:?}; known: {}",
                    known.join(", ")
                )));
            }
        }
        techniques.retain(|t| names.iter().any(|n| n == t.name()));
    }
    let (gpu, gpu_adapter) = match opts.backend {
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
    };
    let mut backends = Vec::new();
    if opts.backend != BackendChoice::Gpu {
        backends.push(Backend::Cpu);
    }
    if gpu.is_some() {
        backends.push(Backend::Gpu);
    }
    let specs = select_scenes(opts)?;
    create_dir(&opts.out)?;
    let per_scene = 1 + (techniques.len() * resolutions.len() * backends.len()) as u64;
    let bar = ProgressBar::new(per_scene * specs.len() as u64);
    bar.set_style(
        ProgressStyle::with_template("{elapsed_precise} [{bar:40}] {pos}/{len} {msg}")
            .unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    let mut report = Report {
        version: 1,
        machine: Machine {
            cpu: cpu_name(),
            threads: rayon::current_num_threads(),
            gpu_adapter,
        },
        references: Vec::new(),
        runs: Vec::new(),
        strips: Vec::new(),
    };
    for spec in specs {
        bar.set_message(format!("{}: reference", spec.name));
        let name = spec.name.clone();
        let p = PreparedScene::new(spec, size, settings)?;
        let reference = p.reference_v();
        let penumbra = reference
            .iter()
            .filter(|&&r| r > crate::metrics::PENUMBRA_LO && r < crate::metrics::PENUMBRA_HI)
            .count();
        report.references.push(ReferenceInfo {
            scene: name.clone(),
            light: p.spec.light.kind().name().into(),
            method: "monte-carlo".into(),
            samples_per_pixel: settings.samples_per_pixel(),
            std_error_255: p.std_error_255(),
            max_std_error_255: p.max_std_error_255(),
            receivers: p.positions.len(),
            penumbra_receivers: penumbra,
            time_ms: p.reference_ms,
        });
        bar.inc(1);
        let exr_dir = opts.out.join("exr").join(&name);
        create_dir(&exr_dir)?;
        write_scene_exr(&exr_dir, size, &p)?;
        let mut strip: Vec<(String, u32, Backend, Vec<f32>)> = Vec::new();
        for t in &techniques {
            for &res in &resolutions {
                for &backend in &backends {
                    bar.set_message(format!(
                        "{name}: {} {} {} {res}",
                        t.name(),
                        t.variant(),
                        backend.name()
                    ));
                    let m = match measure(t.as_ref(), backend, gpu.as_ref(), &p, res) {
                        Ok(m) => m,
                        Err(
                            e @ (ShadowError::InvalidResolution { .. }
                            | ShadowError::UnsupportedLight { .. }),
                        ) => {
                            bar.println(format!(
                                "skipped {name} {} {} {res}: {e}",
                                t.name(),
                                backend.name()
                            ));
                            bar.inc(1);
                            continue;
                        }
                        Err(e) => return Err(e),
                    };
                    let run = Run {
                        scene: name.clone(),
                        technique: t.name().to_string(),
                        variant: t.variant(),
                        backend: backend.name().to_string(),
                        resolution: res,
                        generate_ms: m.generate_ms,
                        evaluate_ms: m.evaluate_ms,
                        errors: errors(&m.v, &reference),
                    };
                    let file = exr_dir.join(format!(
                        "{}-{}-{}-{res}.exr",
                        run.technique, run.variant, run.backend
                    ));
                    images::write_exr_scalar(&file, size, &images::scatter(size, &p.pixels, &m.v))?;
                    let label = format!("{}/{}", run.technique, run.variant);
                    match strip.iter_mut().find(|s| s.0 == label) {
                        Some(s) if (res, backend == Backend::Cpu) > (s.1, s.2 == Backend::Cpu) => {
                            *s = (label, res, backend, m.v)
                        }
                        Some(_) => {}
                        None => strip.push((label, res, backend, m.v)),
                    }
                    report.runs.push(run);
                    bar.inc(1);
                }
            }
        }
        let reference_img = images::scatter(size, &p.pixels, &reference);
        let runs_img: Vec<Vec<Option<f32>>> = strip
            .iter()
            .map(|s| images::scatter(size, &p.pixels, &s.3))
            .collect();
        images::write_strip(
            &opts.out.join(format!("{name}.png")),
            size,
            &reference_img,
            &runs_img,
        )?;
        let scene_runs: Vec<Run> = report
            .runs
            .iter()
            .filter(|r| r.scene == name)
            .cloned()
            .collect();
        pareto::draw(
            &opts.out.join(format!("pareto-{name}.png")),
            &format!("{name}: error vs time"),
            &scene_runs,
        )?;
        let mut columns = vec![format!(
            "reference (monte-carlo, {} spp in penumbra)",
            settings.samples_per_pixel()
        )];
        columns.extend(
            strip
                .iter()
                .map(|s| format!("{} ({} {})", s.0, s.2.name(), s.1)),
        );
        report.strips.push(json::Strip {
            scene: name.clone(),
            file: format!("{name}.png"),
            columns,
        });
    }
    bar.finish_with_message("done");
    pareto::draw(
        &opts.out.join("pareto.png"),
        "all scenes: mean error vs mean time",
        &scene_means(&report.runs),
    )?;
    write_text(
        &opts.out.join("report.json"),
        &serde_json::to_string_pretty(&report)
            .map_err(|e| ShadowError::InvalidScene(e.to_string()))?,
    )?;
    let md = markdown::render(&report);
    write_text(&opts.out.join("report.md"), &md)?;
    write_text(&opts.out.join("index.html"), &html::render(&md))?;
    Ok(report)
}

/// One point per technique/variant/backend/resolution: the mean over scenes of time and error.
fn scene_means(runs: &[Run]) -> Vec<Run> {
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
            o.scene = "all".into();
            o
        })
        .collect()
}

fn write_text(path: &Path, text: &str) -> Result<()> {
    std::fs::write(path, text).map_err(|source| ShadowError::Io {
        path: path.display().to_string(),
        source,
    })
}

fn write_scene_exr(dir: &Path, size: u32, p: &PreparedScene) -> Result<()> {
    let pos: Vec<f32> = p
        .gbuffer
        .data()
        .iter()
        .flat_map(|t| {
            if t.covered {
                t.position.to_array()
            } else {
                [f32::NAN; 3]
            }
        })
        .collect();
    let nrm: Vec<f32> = p
        .gbuffer
        .data()
        .iter()
        .flat_map(|t| {
            if t.covered {
                t.normal.to_array()
            } else {
                [f32::NAN; 3]
            }
        })
        .collect();
    images::write_exr_rgb(&dir.join("gbuffer-position.exr"), size, pos)?;
    images::write_exr_rgb(&dir.join("gbuffer-normal.exr"), size, nrm)?;
    images::write_exr_scalar(
        &dir.join("reference.exr"),
        size,
        &images::scatter(size, &p.pixels, &p.reference_v()),
    )?;
    let se: Vec<f32> = p.reference.iter().map(|r| r.std_error).collect();
    images::write_exr_scalar(
        &dir.join("reference-std-error.exr"),
        size,
        &images::scatter(size, &p.pixels, &se),
    )
}
