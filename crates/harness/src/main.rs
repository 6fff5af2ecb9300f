//! `harness` CLI: `harness report [--quick] [--out DIR] [--scenes a,b] [--techniques x,y]
//! [--resolutions 16,128,512,2048] [--backend cpu|gpu|all] [--scene-file FILE]...` and
//! `harness papers [--out DIR] [--size N]`.

use clap::{Parser, Subcommand, ValueEnum};
use harness::report::{BackendChoice, MemoryBudgets, ReportOptions, run};
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(Parser)]
#[command(
    name = "harness",
    version,
    about = "Soft-shadow techniques against a ray-traced ground truth"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Clone, Copy, ValueEnum)]
enum BackendArg {
    Cpu,
    Gpu,
    All,
}

#[derive(Clone, Copy, ValueEnum)]
enum FramesSceneArg {
    /// The night street (`--lamps` lamps).
    #[value(name = "night-street", alias = "street")]
    Street,
    /// The room with three lamps.
    #[value(name = "room-lamps", alias = "room")]
    Room,
}

#[derive(Subcommand)]
enum Command {
    /// Measure every technique on every scene and write report.json, report.md and pictures.
    Report {
        /// Small G-buffer (128²), one map resolution (256), 16-sample accumulation only, two
        /// timing repetitions: under two minutes on 2 cores.
        #[arg(long)]
        quick: bool,
        /// Print the built-in scenes, the techniques and their variants, then exit.
        #[arg(long)]
        list: bool,
        /// Output directory.
        #[arg(long, default_value = "report")]
        out: PathBuf,
        /// Built-in scenes to run (comma separated; `report --list` names them) [default: all,
        /// or none when --scene-file is given]
        #[arg(long, value_delimiter = ',')]
        scenes: Option<Vec<String>>,
        /// Techniques to run (comma separated): `technique` for every variant, `technique:variant`
        /// for one (such as `pcf:r2`) [default: all]
        #[arg(long, value_delimiter = ',')]
        techniques: Option<Vec<String>>,
        /// Map resolutions, texels per side (comma separated) [default: 16,128,512,2048; with
        /// --quick: 256]
        #[arg(long, value_delimiter = ',')]
        resolutions: Option<Vec<u32>>,
        /// Backends to run.
        #[arg(long, value_enum, default_value = "all")]
        backend: BackendArg,
        /// A user scene (TOML); repeatable.
        #[arg(long = "scene-file")]
        scene_file: Vec<PathBuf>,
        /// G-buffer side in pixels [default: 256; with --quick: 128]
        #[arg(long)]
        size: Option<u32>,
        /// Scenes to draw and measure as a person sees them, 1280 x 720 with FLIP (comma
        /// separated: built-in names or the names of --scene-file scenes; `none` for none)
        /// [default: bunny and the low-poly meshes; with --quick: bunny; with --scenes: those of
        /// them named; none with --scene-file alone]
        #[arg(long = "as-seen", value_delimiter = ',')]
        as_seen: Option<Vec<String>>,
    },
    /// Rebuild each paper's own experiment and write papers.json, papers.md and papers.html.
    Papers {
        /// Output directory.
        #[arg(long, default_value = "report")]
        out: PathBuf,
        /// Side of the ground image in pixels.
        #[arg(long, default_value_t = harness::papers::DEFAULT_SIZE)]
        size: u32,
    },
    /// Draw one scene's reference beside the best variant of each of the four techniques and
    /// the four baselines, labelled with their image errors (the README's picture; CPU).
    Figure {
        /// A built-in scene whose light every technique models.
        #[arg(long, default_value = "triangle-light")]
        scene: String,
        /// The PNG to write.
        #[arg(long, default_value = "docs/techniques.png")]
        out: PathBuf,
        /// Map resolution, texels per side.
        #[arg(long, default_value_t = 512)]
        resolution: u32,
        /// G-buffer side in pixels.
        #[arg(long, default_value_t = 256)]
        size: u32,
        /// Draw the "as seen" figure instead: the bunny's shadow in the 1280 x 720 frame,
        /// cropped, the reference and the techniques' defaults with FLIP under each (`--scene`
        /// and `--size` are not used; `--out docs/as-seen.png --resolution 1024` for the docs).
        #[arg(long)]
        as_seen: bool,
    },
    /// Print the "which technique" table (Markdown) from a report: per light kind and budget,
    /// what to use (the configuration with the lowest image error that fits, paper technique or
    /// baseline) with the Rust expression that builds it, and the best of the other kind beside
    /// it (where a paper technique wins, by how much); each with its FLIP, none that a person
    /// sees as worse than the hard map by FLIP.
    Choose {
        /// The report.json to read.
        #[arg(long, default_value = "report/report.json")]
        report: PathBuf,
        /// The backend whose runs count.
        #[arg(long, value_enum, default_value = "cpu")]
        backend: ChooseBackend,
        /// Budgets per light and frame, milliseconds (comma separated).
        #[arg(long, value_delimiter = ',', default_value = "4,16,64")]
        budgets: Vec<f64>,
    },
    /// The frame pipeline over a camera path down a street at night: each frame's time against
    /// one frame budget shared by every lamp, and every lamp's image error against the
    /// reference.
    Frames {
        /// The scene: the night street, or the room with three lamps.
        #[arg(long, value_enum, default_value = "night-street")]
        scene: FramesSceneArg,
        /// Lamps along the street [default: 16; the room has 3]
        #[arg(long)]
        lamps: Option<usize>,
        /// The frame budget, milliseconds.
        #[arg(long, default_value_t = 16.0)]
        budget_ms: f64,
        /// Frames of the path.
        #[arg(long, default_value_t = 8)]
        frames: u32,
        /// Metres the camera walks a frame.
        #[arg(long, default_value_t = 0.5)]
        step: f32,
        /// The G-buffer's width and height.
        #[arg(long, default_value = "320x180")]
        size: String,
        /// Output file (Markdown).
        #[arg(long, default_value = "report/frames.md")]
        out: PathBuf,
    },
    /// Fit the frame pipeline's `Auto` profile (cost and error models per configuration) from a
    /// report of this machine, and write it for `TechniqueProfile::parse`.
    Profile {
        /// The report.json to fit (a full run: two or more map sides); repeated (runs of the
        /// same configurations on one machine), each run's times are the median over them and
        /// its errors the last one's.
        #[arg(long, default_value = "report/report.json")]
        report: Vec<PathBuf>,
        /// The profile file to write.
        #[arg(long, default_value = "report/profile.txt")]
        out: PathBuf,
        /// A report.json of scenes the fit has not seen (`report --scene-file`): how the fitted
        /// profile predicts them is printed too.
        #[arg(long)]
        held_out: Option<PathBuf>,
    },
}

#[derive(Clone, Copy, ValueEnum)]
enum ChooseBackend {
    Cpu,
    Gpu,
}

/// Says once, before the GPU starts, that Mesa's Vulkan drivers print
/// `error: XDG_RUNTIME_DIR is invalid or not set in the environment.` when that variable is
/// missing (no display server to talk to): the line is the driver's, harmless for headless
/// compute, and setting the variable silences it. Our own errors start `error:` too, so the line
/// is explained rather than filtered; nothing is hidden.
fn explain_driver_noise() {
    let valid =
        std::env::var_os("XDG_RUNTIME_DIR").is_some_and(|d| std::path::Path::new(&d).is_dir());
    if !valid {
        eprintln!(
            "note: XDG_RUNTIME_DIR is not set; the Vulkan driver may print \"error: \
             XDG_RUNTIME_DIR is invalid or not set\" below. It is the driver's, harmless here \
             (no display is used); set XDG_RUNTIME_DIR to silence it."
        );
    }
}

/// A budget in bytes from the environment variable `var`, where it is set and a number.
fn budget_from_env(var: &str) -> Option<u64> {
    std::env::var(var).ok()?.trim().parse().ok()
}

fn report_error(e: &harness::error::HarnessError) -> ExitCode {
    eprintln!("error: {e}");
    let mut src = std::error::Error::source(e);
    while let Some(s) = src {
        eprintln!("  caused by: {s}");
        src = s.source();
    }
    ExitCode::FAILURE
}

fn main() -> ExitCode {
    let result = match Cli::parse().command {
        Command::Report { quick, list, .. } if list => {
            print!("{}", harness::report::listing(quick));
            return ExitCode::SUCCESS;
        }
        Command::Report {
            quick,
            out,
            scenes,
            techniques,
            resolutions,
            backend,
            scene_file,
            size,
            as_seen,
            ..
        } => {
            let opts = ReportOptions {
                quick,
                out: out.clone(),
                scenes,
                techniques,
                registry: soft_shadow_techniques::registry(),
                resolutions,
                backend: match backend {
                    BackendArg::Cpu => BackendChoice::Cpu,
                    BackendArg::Gpu => BackendChoice::Gpu,
                    BackendArg::All => BackendChoice::All,
                },
                scene_files: scene_file,
                size,
                as_seen: as_seen.map(|v| v.into_iter().filter(|n| n != "none").collect()),
                memory: MemoryBudgets {
                    cpu: budget_from_env("SHADOW_CPU_MEMORY_BUDGET"),
                    gpu: budget_from_env("SHADOW_GPU_MEMORY_BUDGET"),
                },
            };
            if opts.backend != BackendChoice::Cpu {
                explain_driver_noise();
            }
            run(&opts).map(|r| {
                let walks = match r.frames.len() {
                    0 => String::new(),
                    n => format!(" and {n} walks of many lamps"),
                };
                format!(
                    "wrote {} runs over {} scenes{walks} to {}",
                    r.runs.len(),
                    r.references.len(),
                    out.display()
                )
            })
        }
        Command::Papers { out, size } => {
            let opts = harness::papers::PapersOptions {
                out: out.clone(),
                size,
            };
            harness::papers::run(&opts).map(|p| {
                format!(
                    "wrote {} experiments ({} runs) to {}",
                    p.experiments.len(),
                    p.runs.len(),
                    out.join("papers.md").display()
                )
            })
        }
        Command::Figure {
            out,
            resolution,
            as_seen: true,
            ..
        } => harness::figure::as_seen(&out, resolution).map(|scores| {
            let mut s = String::new();
            for (label, flip) in scores {
                s.push_str(&format!("{label}: mean FLIP {flip:.4}\n"));
            }
            s + &format!("wrote {}", out.display())
        }),
        Command::Figure {
            scene,
            out,
            resolution,
            size,
            ..
        } => {
            let opts = harness::figure::FigureOptions {
                scene,
                out: out.clone(),
                resolution,
                size,
            };
            harness::figure::run(&opts).map(|columns| {
                let mut s = String::new();
                for c in columns {
                    s.push_str(&format!(
                        "{} {}: image error {:.2}/255, V error {:.2}/255\n",
                        c.technique, c.variant, c.image_rms_255, c.rms_255
                    ));
                }
                s + &format!("wrote {}", out.display())
            })
        }
        Command::Profile {
            report,
            out,
            held_out,
        } => harness::profile::write(&report, &out).and_then(|(p, v)| {
            let share = |what: &str, v: &harness::profile::Validation| {
                format!(
                    "; {what}, {:.1}% of predicted times within 1.5x, {:.1}% of Auto's picks \
                     within budget, mean regret {:.2}/255",
                    100.0 * v.time_share(),
                    100.0 * v.within_budget_share(),
                    v.mean_regret()
                )
            };
            let mut line = format!(
                "wrote {} configurations to {}",
                p.entries.len(),
                out.display()
            );
            if let Some(v) = v {
                line += &share("on scenes left out of the fit", &v);
            }
            if let Some(path) = held_out {
                let other = harness::profile::read_report(&path)?;
                line += &share(
                    &format!("on the scenes of {}", path.display()),
                    &harness::profile::held_out(&p, &other),
                );
            }
            Ok(line)
        }),
        Command::Frames {
            scene,
            lamps,
            budget_ms,
            frames,
            step,
            size,
            out,
        } => harness::frames::run(
            match scene {
                FramesSceneArg::Street => harness::frames::FramesScene::Street,
                FramesSceneArg::Room => harness::frames::FramesScene::Room,
            },
            lamps,
            budget_ms,
            frames,
            step,
            &size,
            &out,
        ),
        Command::Choose {
            report,
            backend,
            budgets,
        } => harness::report::summary::choices_from_file(
            &report,
            match backend {
                ChooseBackend::Cpu => "cpu",
                ChooseBackend::Gpu => "gpu",
            },
            &budgets,
        ),
    };
    match result {
        Ok(line) => {
            println!("{line}");
            ExitCode::SUCCESS
        }
        Err(e) => report_error(&e),
    }
}
