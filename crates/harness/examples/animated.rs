//! The frame pipeline on a small animated scene ([`harness::animated`]): five lights of different
//! kinds, one caster orbiting between them, one static. Prints each frame's statistics (static
//! lights and static frames reuse their maps) and writes the last frame as `animated.png`: per
//! pixel the mean visibility of the lights whose range reaches it.
//!
//! `cargo run --release --example animated [-- --gpu] [--frames N] [--out FILE]`;
//! unknown or malformed flags are refused with clap's usage message, errors print as
//! `error: ...` with a non-zero exit.

use clap::Parser;
use glam::Vec3;
use harness::animated::{AnimatedScene, pipeline};
use shadow_frame::scene::LightSource;
use shadow_frame::{FrameBackend, LightState, ResolvedTechnique, ShadowConfig, influence};
use soft_shadow_core::GpuContext;
use std::path::PathBuf;
use std::process::ExitCode;
use std::sync::Arc;

/// The frame pipeline on a small animated scene.
#[derive(Parser)]
#[command(name = "animated")]
struct Args {
    /// Run the techniques on the GPU.
    #[arg(long)]
    gpu: bool,
    /// Frames to run.
    #[arg(long, default_value_t = 30, value_parser = clap::value_parser!(u32).range(1..))]
    frames: u32,
    /// The last frame's image.
    #[arg(long, default_value = "animated.png")]
    out: PathBuf,
}

fn main() -> ExitCode {
    match run(Args::parse()) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            let mut source = std::error::Error::source(&e);
            while let Some(s) = source {
                eprintln!("  caused by: {s}");
                source = s.source();
            }
            ExitCode::FAILURE
        }
    }
}

fn run(args: Args) -> harness::error::Result<()> {
    let (frames, out) = (args.frames, args.out);
    let size = 384;
    let mut lab = AnimatedScene::new(size, 512)?;
    if args.gpu {
        lab.scene
            .world
            .insert_resource(FrameBackend::gpu(Arc::new(GpuContext::new()?)));
    }
    let mut pipeline = pipeline();
    for f in 0..frames {
        lab.step(f, frames);
        println!("{}", pipeline.run(&mut lab.scene.world).summary());
    }
    let world = &lab.scene.world;
    for &e in &lab.lights {
        let light = world.get::<LightSource>(e).expect("light").0;
        match (
            world.get::<ResolvedTechnique>(e),
            world.get::<LightState>(e),
        ) {
            (Some(r), _) => println!(
                "{} light: {} {} ({})",
                light.kind().name(),
                r.technique.name(),
                r.technique.variant(),
                r.reason
            ),
            (None, Some(s)) => {
                println!("{} light: no shadows ({:?})", light.kind().name(), s.error)
            }
            _ => {}
        }
    }
    // Each pixel: the mean visibility of the lights whose range reaches it; 0.15 where none does.
    let mut image = image::GrayImage::new(size, size);
    let lit: Vec<((Vec3, f32), &LightState)> = lab
        .lights
        .iter()
        .filter_map(|&e| {
            let light = world.get::<LightSource>(e)?.0;
            let range = world.get::<ShadowConfig>(e)?.range;
            Some((influence(&light, range), world.get::<LightState>(e)?))
        })
        .collect();
    for (k, &i) in lab.pixels.iter().enumerate() {
        let p = lab.gbuffer.data()[i].position;
        let near: Vec<f32> = lit
            .iter()
            .filter(|((c, r), _)| p.distance(*c) <= *r)
            .map(|(_, s)| s.visibility.get(k).copied().unwrap_or(1.0))
            .collect();
        let v = if near.is_empty() {
            0.15
        } else {
            near.iter().sum::<f32>() / near.len() as f32
        };
        image.put_pixel(
            i as u32 % size,
            i as u32 / size,
            image::Luma([(v * 255.0).round() as u8]),
        );
    }
    image
        .save(&out)
        .map_err(|e| harness::error::HarnessError::write(&out, e))?;
    println!("wrote {}", out.display());
    Ok(())
}
