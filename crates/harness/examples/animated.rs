//! The frame pipeline on a small animated scene ([`harness::animated`]): five lights of different
//! kinds, one caster orbiting between them, one static. Prints each frame's statistics (static
//! lights and static frames reuse their maps) and writes the last frame as `animated.png`: per
//! pixel the mean visibility of the lights whose range reaches it.
//!
//! `cargo run --release -p harness --example animated [-- --gpu] [--frames N] [--out FILE]`

use glam::Vec3;
use harness::animated::{AnimatedScene, pipeline};
use shadow_core::frame::{FrameBackend, LightState, ResolvedTechnique, ShadowConfig, influence};
use shadow_core::scene::LightSource;
use shadow_core::{Backend, GpuContext};
use std::sync::Arc;

fn arg<T: std::str::FromStr>(name: &str) -> Option<T> {
    let args: Vec<String> = std::env::args().collect();
    args.iter()
        .position(|a| a == name)
        .and_then(|i| args.get(i + 1))
        .and_then(|v| v.parse().ok())
}

fn main() -> shadow_core::Result<()> {
    let frames: u32 = arg("--frames").unwrap_or(30);
    let out: String = arg("--out").unwrap_or_else(|| "animated.png".into());
    let size = 384;
    let mut lab = AnimatedScene::new(size, 512)?;
    if std::env::args().any(|a| a == "--gpu") {
        lab.scene.world.insert_resource(FrameBackend {
            backend: Backend::Gpu,
            gpu: Some(Arc::new(GpuContext::new()?)),
        });
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
        .map_err(|e| shadow_core::ShadowError::Gpu(format!("writing {out}: {e}")))?;
    println!("wrote {out}");
    Ok(())
}
