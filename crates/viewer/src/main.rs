//! `viewer`: opens a window showing a scene shadowed by one technique (or two, split), with a
//! panel to change scene, light, technique, variant, map side and view. With `--frames` it
//! renders that many frames in the window, writes `--screenshot` and exits.
//!
//! `cargo run --release --bin viewer -- --scene bunny --technique occlusion-slices`

use clap::Parser;
use soft_shadow_core::LightKind;
use std::path::PathBuf;
use viewer::ViewMode;
use viewer::app::{Options, run};
use viewer::scene::SceneSource;

/// Command-line options.
#[derive(Parser, Debug)]
#[command(about, long_about = None)]
struct Args {
    /// A catalogue scene (bunny, torus, contact, ...), or a scene of lamps under one frame
    /// budget (night-street, room-lamps: the budget picks each lamp's technique and map side,
    /// so --technique, --variant, --compare, --resolution and --light do not apply, and the
    /// view is shaded or v).
    #[arg(long, default_value = "bunny", conflicts_with = "open")]
    scene: String,
    /// A scene file (.toml) or a glTF model (.glb, .gltf) instead.
    #[arg(long)]
    open: Option<PathBuf>,
    /// hard, pcf, pcss, accumulation, penumbra-limit, occlusion-slices, linear-light or
    /// shadow-width.
    #[arg(long, default_value = "penumbra-limit")]
    technique: String,
    /// The technique's variant (its default where not given).
    #[arg(long)]
    variant: Option<String>,
    /// A second technique, right of the split.
    #[arg(long)]
    compare: Option<String>,
    /// Side of the maps.
    #[arg(long, default_value_t = 1024)]
    resolution: u32,
    /// Size of the 3D view, WIDTHxHEIGHT (the window adds the panel).
    #[arg(long, default_value = "1280x720", value_parser = parse_size)]
    size: (u32, u32),
    /// shaded, v, error or views (the light's views: frustum, cube faces or cascades).
    #[arg(long, default_value = "shaded", value_parser = parse_mode)]
    view: ViewMode,
    /// Turn the light.
    #[arg(long)]
    animate: bool,
    /// The light's kind instead of the scene's (point, linear, rect, disk, triangle, sphere,
    /// distant), at the same place and size.
    #[arg(long, value_parser = parse_kind)]
    light: Option<LightKind>,
    /// Render this many frames, then exit (command-line mode).
    #[arg(long)]
    frames: Option<u32>,
    /// With --frames: write the last frame (the whole window) to this PNG.
    #[arg(long, requires = "frames")]
    screenshot: Option<PathBuf>,
    /// The frame budget the lamps of a scene of lamps (night-street, room-lamps) share,
    /// milliseconds.
    #[arg(long, default_value_t = viewer::lamps::BUDGET_MS, value_parser = parse_budget)]
    budget_ms: f64,
}

fn parse_budget(s: &str) -> Result<f64, String> {
    s.parse::<f64>()
        .ok()
        .filter(|ms| ms.is_finite() && *ms > 0.0)
        .ok_or_else(|| format!("{s:?} is not a positive number of milliseconds"))
}

fn parse_size(s: &str) -> Result<(u32, u32), String> {
    let (w, h) = s
        .split_once('x')
        .ok_or_else(|| format!("{s:?} is not WIDTHxHEIGHT"))?;
    let n = |v: &str| {
        v.parse::<u32>()
            .ok()
            .filter(|&n| (16..=8192).contains(&n))
            .ok_or_else(|| format!("{v:?} is not a size from 16 to 8192"))
    };
    Ok((n(w)?, n(h)?))
}

fn parse_kind(s: &str) -> Result<LightKind, String> {
    LightKind::ALL
        .into_iter()
        .find(|k| k.name() == s)
        .ok_or_else(|| format!("{s:?} is not a light kind"))
}

fn parse_mode(s: &str) -> Result<ViewMode, String> {
    ViewMode::ALL
        .into_iter()
        .find(|m| m.name() == s)
        .ok_or_else(|| format!("{s:?} is not shaded, v, error or views"))
}

fn main() {
    let args = Args::parse();
    let options = Options {
        scene: match args.open {
            Some(path) => SceneSource::File(path),
            None => SceneSource::Catalogue(args.scene),
        },
        technique: args.technique,
        variant: args.variant,
        compare: args.compare,
        resolution: args.resolution,
        view_size: args.size,
        mode: args.view,
        animate: args.animate,
        light: args.light,
        frames: args.frames,
        screenshot: args.screenshot,
        budget_ms: args.budget_ms,
    };
    if let Err(e) = run(options) {
        eprintln!("error: {e}");
        std::process::exit(1);
    }
}
