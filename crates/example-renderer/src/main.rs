//! Renders PNG frames of a glTF model under a moving area light, shadowed by the technique
//! named on the command line, on a device the renderer creates itself.
//!
//! `cargo run --release --bin example-renderer -- --technique occlusion-slices --frames 8`

use clap::Parser;
use example_renderer::{
    FrameSettings, Renderer, model_on_ground, moving_light, moving_triangle, own_device,
};
use soft_shadow_core::{LightKind, ShadowError, ShadowTechnique};
use std::path::PathBuf;

/// Command-line options.
#[derive(Parser, Debug)]
#[command(about, long_about = None)]
struct Args {
    /// hard, pcf, pcss, accumulation, penumbra-limit, occlusion-slices, linear-light or
    /// shadow-width.
    #[arg(long, default_value = "pcss")]
    technique: String,
    /// A .glb/.gltf model.
    #[arg(long, default_value = "assets/stanford-bunny.glb")]
    model: PathBuf,
    /// Frames over one turn of the light.
    #[arg(long, default_value_t = 8)]
    frames: u32,
    /// Image width and height in pixels.
    #[arg(long, default_value_t = 512)]
    size: u32,
    /// Side of the technique's maps.
    #[arg(long, default_value_t = 1024)]
    resolution: u32,
    /// Folder the frames are written to (`frame-000.png`, ...).
    #[arg(long, default_value = "renderer-frames")]
    out: PathBuf,
}

/// What `main` reports: the library's error, or a frame that could not be written.
type Result<T> = std::result::Result<T, Box<dyn std::error::Error>>;

fn run<T: ShadowTechnique>(technique: T, args: &Args) -> Result<()> {
    let model = shadow_frame::gltf::import_gltf_file(&args.model)?;
    let (geometry, camera) = model_on_ground(&model);
    let (device, queue) = own_device()?;
    let settings = FrameSettings {
        width: args.size,
        height: args.size,
        resolution: args.resolution,
        camera,
    };
    // A square light, or a triangle of the same area for techniques without squares.
    let light = if technique.models(LightKind::Rect) {
        moving_light
    } else {
        moving_triangle
    };
    let renderer = Renderer::new(device, queue, technique, &geometry, settings)?;
    std::fs::create_dir_all(&args.out).map_err(|source| ShadowError::Io {
        path: args.out.display().to_string(),
        source,
    })?;
    for i in 0..args.frames {
        renderer.render(&light(i, args.frames))?;
        let path = args.out.join(format!("frame-{i:03}.png"));
        renderer
            .read_color()?
            .save(&path)
            .map_err(|e| format!("cannot write {}: {e}", path.display()))?;
        println!("{}", path.display());
    }
    Ok(())
}

fn main() {
    let args = Args::parse();
    use shadow_maps::{Filter, ShadowMapBaseline};
    let out = match args.technique.as_str() {
        "hard" => run(ShadowMapBaseline::new(Filter::Hard), &args),
        "pcf" => run(ShadowMapBaseline::new(Filter::Pcf { radius: 2 }), &args),
        "pcss" => run(ShadowMapBaseline::new(Filter::Pcss), &args),
        "accumulation" => run(
            ShadowMapBaseline::new(Filter::Accumulate { samples: 16 }),
            &args,
        ),
        "penumbra-limit" => run(
            penumbra_limit::PenumbraLimit::new(penumbra_limit::Generator::Silhouette),
            &args,
        ),
        "occlusion-slices" => run(
            occlusion_slices::OcclusionSlices::new(8, occlusion_slices::Prefilter::NBuffer),
            &args,
        ),
        "linear-light" => run(linear_light::LinearLight::new(4), &args),
        "shadow-width" => run(
            shadow_width::ShadowWidth::new(shadow_width::WidthMethod::Exact),
            &args,
        ),
        other => Err(
            ShadowError::InvalidScene(format!("unknown technique {other:?}; see --help")).into(),
        ),
    };
    if let Err(e) = out {
        eprintln!("error: {e}");
        std::process::exit(1);
    }
}
