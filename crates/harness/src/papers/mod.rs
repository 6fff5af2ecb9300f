//! The `papers` subcommand: each technique paper's own experiment, rebuilt as the paper
//! describes it, run through the report's reference and metrics, with the paper's published
//! numbers (or ordering) beside ours and a verdict per claim.
//!
//! One module per paper: [`lawlor`] (Figures 10-11), [`heidrich`] (Figures 8-9), [`eisemann`]
//! (Figures 2, 3, 6), [`kirsch`] (Figures 6, 7, Table 1). Every experiment runs on the CPU
//! backend (the GPU paths are held to the CPU's output by the test suite) over a top-down
//! camera that sees only the ground, so every error is the shadow cast on the ground plane, as
//! in the papers' figures. `papers.json` keeps the report's run schema (scene names say the
//! paper and figure, such as `lawlor-fig10`); `papers.md` and `papers.html` print one table per
//! experiment and one verdict per claim.

pub mod eisemann;
pub mod heidrich;
pub mod kirsch;
pub mod lawlor;

use crate::metrics::errors;
use crate::report::json::Run;
use crate::report::measure::measure;
use crate::setup::PreparedScene;
use glam::Vec3;
use serde::Serialize;
use soft_shadow_core::{Camera, DynTechnique, Light, LightPoint, Result};
use soft_shadow_reference::ground_truth::{GroundTruthSettings, RayTracer};
use soft_shadow_reference::scenes::{MeshInstance, SceneSpec};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::Instant;

/// What `papers` runs and where it writes.
#[derive(Clone, Debug)]
pub struct PapersOptions {
    /// Output directory (`papers.json`, `papers.md`, `papers.html`).
    pub out: PathBuf,
    /// G-buffer side of the ground image, pixels.
    pub size: u32,
}

impl Default for PapersOptions {
    fn default() -> Self {
        Self {
            out: PathBuf::from("report"),
            size: DEFAULT_SIZE,
        }
    }
}

/// G-buffer side of the ground image by default.
pub const DEFAULT_SIZE: u32 = 128;

/// Everything `papers` measured.
#[derive(Clone, Debug, Serialize)]
pub struct Papers {
    /// Format version (1).
    pub version: u32,
    /// One entry per experiment.
    pub experiments: Vec<Experiment>,
    /// Every measured configuration, in `report.json`'s run schema.
    pub runs: Vec<Run>,
}

/// One paper's experiment: a table of published numbers beside ours, and its claims.
#[derive(Clone, Debug, Serialize)]
pub struct Experiment {
    /// Scene name of its runs, such as `lawlor-fig10`.
    pub id: String,
    /// Paper, such as "Lawlor 2006, Interpolation-friendly soft shadow maps".
    pub paper: String,
    /// Figure or table reproduced.
    pub figure: String,
    /// How the experiment is set up here, and what differs from the paper.
    pub setup: String,
    /// What the numbers are (metric and scale).
    pub metric: String,
    /// Column headings (resolutions, or metric names).
    pub columns: Vec<String>,
    /// Table rows.
    pub rows: Vec<Row>,
    /// The paper's claims with our verdict.
    pub claims: Vec<Claim>,
}

/// One table row: the paper's number and ours per column.
#[derive(Clone, Debug, Serialize)]
pub struct Row {
    /// What the row measures.
    pub label: String,
    /// Published values (`None`: not published).
    pub published: Vec<Option<f64>>,
    /// Our values (`None`: not measured, with the reason in the setup text).
    pub ours: Vec<Option<f64>>,
}

/// A published claim and whether our measurement reproduces it.
#[derive(Clone, Debug, Serialize)]
pub struct Claim {
    /// The claim, as the paper states it.
    pub claim: String,
    /// Whether our numbers show it.
    pub holds: bool,
    /// The numbers the verdict rests on.
    pub measured: String,
}

impl Claim {
    /// A claim with its verdict and the measurement behind it.
    pub fn new(claim: &str, holds: bool, measured: String) -> Self {
        Self {
            claim: claim.into(),
            holds,
            measured,
        }
    }
}

impl Experiment {
    /// The claim whose text starts with `prefix`.
    pub fn claim(&self, prefix: &str) -> Option<&Claim> {
        self.claims.iter().find(|c| c.claim.starts_with(prefix))
    }

    /// Our value in row `label`, column `col`.
    pub fn ours(&self, label: &str, col: usize) -> Option<f64> {
        self.rows
            .iter()
            .find(|r| r.label == label)
            .and_then(|r| r.ours.get(col).copied().flatten())
    }
}

/// Runs every experiment at G-buffer side `size`, in the order of the module docs.
pub fn run_all(size: u32) -> crate::error::Result<Papers> {
    let mut experiments = Vec::new();
    let mut runs = Vec::new();
    type Exp = fn(u32) -> Result<(Vec<Experiment>, Vec<Run>)>;
    let all: [(&str, Exp); 4] = [
        ("lawlor", lawlor::run),
        ("heidrich", heidrich::run),
        ("eisemann", eisemann::run),
        ("kirsch", kirsch::run),
    ];
    for (name, f) in all {
        let t = Instant::now();
        let (e, r) = f(size)?;
        println!("papers: {name} in {:.1} s", t.elapsed().as_secs_f64());
        experiments.extend(e);
        runs.extend(r);
    }
    Ok(Papers {
        version: 1,
        experiments,
        runs,
    })
}

/// Runs every experiment and writes `papers.json`, `papers.md` and `papers.html` into `opts.out`.
pub fn run(opts: &PapersOptions) -> crate::error::Result<Papers> {
    let papers = run_all(opts.size)?;
    write(&papers, &opts.out)?;
    Ok(papers)
}

/// Writes the three files.
pub fn write(papers: &Papers, out: &Path) -> crate::error::Result<()> {
    crate::files::create_dir(out)?;
    let json = serde_json::to_string_pretty(papers)
        .map_err(|e| crate::error::HarnessError::write(&out.join("papers.json"), e))?;
    let md = markdown(papers);
    crate::files::write_text(&out.join("papers.json"), &json)?;
    crate::files::write_text(&out.join("papers.html"), &crate::report::html::render(&md))?;
    crate::files::write_text(&out.join("papers.md"), &md)
}

fn cell(v: Option<f64>) -> String {
    v.map_or("—".into(), |x| format!("{x:.1}"))
}

/// `papers.md`: per experiment its setup, one table (published / ours per column) and the
/// verdict per claim.
pub fn markdown(papers: &Papers) -> String {
    let mut s = String::from(
        "# The papers' own experiments\n\nEach paper's experiment rebuilt as it describes it, \
         measured against the ray-traced reference (`docs/ground-truth.md`) on the CPU backend, written by `cargo run --release --bin harness -- papers --out docs`. Cells \
         read `published / ours`; a dash is a number the paper does not publish or a \
         technique we do not implement.\n",
    );
    for e in &papers.experiments {
        let _ = write!(
            s,
            "\n## {} — {} (`{}`)\n\n{}\n\nMetric: {}\n\n| | {} |\n|---|{}\n",
            e.paper,
            e.figure,
            e.id,
            e.setup,
            e.metric,
            e.columns.join(" | "),
            "---:|".repeat(e.columns.len())
        );
        for r in &e.rows {
            let cells: Vec<String> = (0..e.columns.len())
                .map(|i| {
                    format!(
                        "{} / {}",
                        cell(r.published.get(i).copied().flatten()),
                        cell(r.ours.get(i).copied().flatten())
                    )
                })
                .collect();
            let _ = writeln!(s, "| {} | {} |", r.label, cells.join(" | "));
        }
        s.push_str("\n| claim | verdict | measured |\n|---|---|---|\n");
        for c in &e.claims {
            let _ = writeln!(
                s,
                "| {} | {} | {} |",
                c.claim,
                if c.holds {
                    "reproduced"
                } else {
                    "not reproduced"
                },
                c.measured
            );
        }
    }
    s
}

/// A scene of the papers: a ground that only receives plus `casters` (which do not receive,
/// so the top-down camera sees the whole shadow on the ground), seen from above over the square
/// of half side `half` around `center`.
pub fn scene(
    name: &str,
    description: &str,
    casters: Vec<soft_shadow_core::TriangleMesh>,
    light: Light,
    center: Vec3,
    half: f32,
) -> SceneSpec {
    let inst = |mesh, caster: bool| MeshInstance {
        mesh: Arc::new(mesh),
        transform: glam::Mat4::IDENTITY,
        caster,
        receiver: !caster,
    };
    let mut meshes = vec![inst(
        soft_shadow_reference::scenes::shapes::ground(20.0, 0.0, 1),
        false,
    )];
    meshes.extend(casters.into_iter().map(|m| inst(m, true)));
    let height = 40.0;
    SceneSpec {
        name: name.into(),
        description: description.into(),
        hard_case: false,
        meshes,
        light,
        camera: Camera {
            eye: center + Vec3::Y * height,
            target: center,
            fov_y: 2.0 * (half / height).atan(),
            near: 1.0,
            far: 100.0,
        },
    }
}

/// A prepared papers scene: its ground receivers and reference.
pub fn prepare(spec: SceneSpec, size: u32) -> Result<PreparedScene> {
    PreparedScene::new(spec, size, GroundTruthSettings::default())
}

/// Measures `t` once on the CPU at `resolution` against `reference` (default: the scene's), as a run
/// of scene `id`, and returns the run and `V`.
pub fn measure_run(
    id: &str,
    t: &dyn DynTechnique,
    p: &PreparedScene,
    resolution: u32,
    reference: Option<&[f32]>,
) -> Result<(Run, Vec<f32>)> {
    measure_run_reps(id, t, p, resolution, reference, 1)
}

/// [`measure_run`] with the median times of `reps` timed frames (fewer where
/// [`crate::report::measure::REP_BUDGET_S`] runs out), for the experiments that compare times.
pub fn measure_run_reps(
    id: &str,
    t: &dyn DynTechnique,
    p: &PreparedScene,
    resolution: u32,
    reference: Option<&[f32]>,
    reps: usize,
) -> Result<(Run, Vec<f32>)> {
    let cpu = soft_shadow_core::CpuContext::new();
    let m = measure(
        t,
        soft_shadow_core::Context::Cpu(&cpu),
        p,
        resolution,
        reps,
        false,
        None,
    )?;
    let own = p.reference_v();
    let reference = reference.unwrap_or(&own);
    let run = Run {
        scene: id.into(),
        technique: t.name().into(),
        variant: t.variant(),
        backend: "cpu".into(),
        resolution,
        generate_ms: m.generate_ms,
        evaluate_ms: m.evaluate_ms,
        errors: errors(&m.v, reference, &p.shading),
        flicker_255: None,
        ..Default::default()
    };
    Ok((run, m.v))
}

/// `V` of every receiver of `p` from exact rays to the weighted light `points` (points that do
/// not reach a receiver are left out, visibility v2), as a run of scene `id` with technique
/// `ray-traced` and variant `label` (resolution 0: no map).
pub fn ray_traced_run(
    id: &str,
    label: &str,
    p: &PreparedScene,
    points: impl Fn(Vec3) -> Vec<(LightPoint, f32)>,
) -> (Run, Vec<f32>) {
    let t = Instant::now();
    let tracer = RayTracer::new(&p.geometry.casters);
    let light = &p.spec.light;
    let v: Vec<f32> = p
        .positions
        .iter()
        .zip(&p.normals)
        .map(|(&q, &n)| {
            let (mut seen, mut total) = (0.0f32, 0.0f32);
            for (x, w) in points(q) {
                if light.reaches(x, q, n) {
                    total += w;
                    if tracer.sees(q, n, x) {
                        seen += w;
                    }
                }
            }
            if total > 0.0 { seen / total } else { 1.0 }
        })
        .collect();
    let run = Run {
        scene: id.into(),
        technique: "ray-traced".into(),
        variant: label.into(),
        backend: "cpu".into(),
        resolution: 0,
        generate_ms: 0.0,
        evaluate_ms: t.elapsed().as_secs_f64() * 1e3,
        errors: errors(&v, &p.reference_v(), &p.shading),
        flicker_255: None,
        ..Default::default()
    };
    (run, v)
}

/// RMS of `(v - reference) * 255` over the receivers `keep` selects.
pub fn rms_where(v: &[f32], reference: &[f32], keep: impl Fn(usize) -> bool) -> f64 {
    let (a, b): (Vec<f32>, Vec<f32>) = (0..v.len())
        .filter(|&i| keep(i))
        .map(|i| (v[i], reference[i]))
        .unzip();
    crate::metrics::rms_255(&a, &b)
}
