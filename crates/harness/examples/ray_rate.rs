//! Shadow-ray throughput of the ground truth's tracers on catalogue scenes, per core: ray by ray
//! through `obvhs`'s CWBVH (`RayTracer::unoccluded`), and each receiver's rays together as the
//! reference traces them (`OriginRays`: its candidate casters found and binned once, that setup
//! timed with the rays). The same rays are written out so that another tracer can be timed on
//! exactly them (`benches/embree_rays.py` times Embree).
//!
//! The rays are the reference's kind: from every receiver of the camera's G-buffer that is not
//! proven lit, `--per-receiver` points of the light drawn uniformly, kept where they reach the
//! receiver, each ray from the receiver offset along its normal (the reference's relative
//! offset) to the light point, or to infinity for a distant light.
//!
//! ```sh
//! cargo run --release --example ray_rate -- --out rays
//! python3 benches/embree_rays.py rays
//! ```
//!
//! Output: one line per scene, tracer and thread count, `scene tracer threads rays
//! M_rays_per_s_per_core lit_fraction` (the fraction of rays that reach the light unoccluded),
//! with `tracer` `cwbvh` (ray by ray) or `origin` (per receiver).
//! With `--out DIR`, `DIR/<scene>.tris` (f32 x 9 per triangle) and `DIR/<scene>.rays` (f32 x 8
//! per ray: origin, direction, t_min, t_max), little-endian.

use clap::Parser;
use glam::Vec3;
use harness::metrics::median;
use rayon::prelude::*;
use soft_shadow_core::LightPoint;
use soft_shadow_reference::ground_truth::{GroundTruthSettings, RayTracer};
use soft_shadow_reference::scenes::catalogue::build;
use soft_shadow_reference::scenes::scene_receivers;
use std::path::PathBuf;
use std::time::Instant;

#[derive(Parser)]
struct Args {
    /// Catalogue scenes, comma-separated.
    #[arg(
        long,
        value_delimiter = ',',
        default_value = "torus,bunny,foliage,overlap"
    )]
    scenes: Vec<String>,
    /// G-buffer side.
    #[arg(long, default_value_t = 48)]
    size: u32,
    /// Light points drawn per receiver not proven lit (the reference draws 4096: 32² strata in
    /// each of 4 replicates).
    #[arg(long, default_value_t = 4096)]
    per_receiver: u32,
    /// Repetitions timed (the median is printed).
    #[arg(long, default_value_t = 3)]
    reps: usize,
    /// Where to write the rays and triangles (nothing is written without it).
    #[arg(long)]
    out: Option<PathBuf>,
}

/// One shadow ray: origin, unit direction, t range.
#[derive(Clone, Copy)]
struct ShadowRay {
    origin: Vec3,
    dir: Vec3,
    t_min: f32,
    t_max: f32,
}

fn rand01(i: u64) -> f32 {
    let mut x = i.wrapping_mul(0x9E37_79B9_7F4A_7C15);
    x ^= x >> 31;
    x = x.wrapping_mul(0xBF58_476D_1CE4_E5B9);
    x ^= x >> 29;
    (x >> 40) as f32 / (1u64 << 24) as f32
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args = Args::parse();
    let offset = GroundTruthSettings::default().ray_offset;
    if let Some(dir) = &args.out {
        std::fs::create_dir_all(dir)?;
    }
    println!("scene tracer threads rays M_rays_per_s_per_core lit_fraction");
    for name in &args.scenes {
        let spec = build(name)?;
        let (geometry, positions, normals) = scene_receivers(&spec, args.size)?;
        let tracer = RayTracer::new(&geometry.casters);
        let light = spec.light;
        let mut rays = Vec::new();
        // Receivers traced: position, normal, their rays' range in `rays`.
        let mut receivers = Vec::new();
        for (i, (&p, &n)) in positions.iter().zip(&normals).enumerate() {
            if !light.reaches_any(p, n) || tracer.proven_lit(&light, p, n, offset) {
                continue;
            }
            let first = rays.len();
            let eps = offset * (p.abs().max_element() + 0.01);
            let origin = p + n * eps;
            for k in 0..args.per_receiver {
                let s = (i as u64) << 20 | k as u64;
                let u = glam::Vec2::new(rand01(2 * s), rand01(2 * s + 1));
                let (q, _) = light.sample(u, p);
                if !light.reaches(q, p, n) {
                    continue;
                }
                rays.push(match q {
                    LightPoint::Position(x) => {
                        let d = x - origin;
                        let len = d.length();
                        ShadowRay {
                            origin,
                            dir: d / len,
                            t_min: eps,
                            t_max: len * (1.0 - 1e-5),
                        }
                    }
                    LightPoint::Direction(d) => ShadowRay {
                        origin,
                        dir: d,
                        t_min: eps,
                        t_max: f32::INFINITY,
                    },
                });
            }
            receivers.push((p, n, first..rays.len()));
        }
        if rays.is_empty() {
            println!("{name}: no ray (every receiver proven lit)");
            continue;
        }
        let cwbvh = |r: &ShadowRay| tracer.unoccluded(r.origin, r.dir, r.t_min, r.t_max);
        let origin = |(p, n, range): &(Vec3, Vec3, std::ops::Range<usize>)| {
            let Some(together) = tracer.origin_rays(&light, *p, *n, offset) else {
                return rays[range.clone()].iter().filter(|r| cwbvh(r)).count();
            };
            rays[range.clone()]
                .iter()
                .filter(|r| together.unoccluded(r.dir, r.t_min, r.t_max))
                .count()
        };
        for threads in [1, rayon::current_num_threads()] {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()?;
            for tracer in ["cwbvh", "origin"] {
                let mut lit = 0;
                let times: Vec<f64> = (0..args.reps)
                    .map(|_| {
                        let t = Instant::now();
                        lit = pool.install(|| match tracer {
                            "cwbvh" => rays.par_iter().filter(|r| cwbvh(r)).count(),
                            _ => receivers.par_iter().map(origin).sum(),
                        });
                        t.elapsed().as_secs_f64()
                    })
                    .collect();
                let rate = rays.len() as f64 / median(&times) / threads as f64 / 1e6;
                let lit = lit as f64 / rays.len() as f64;
                println!(
                    "{name} {tracer} {threads} {} {rate:.2} {lit:.4}",
                    rays.len()
                );
            }
        }
        if let Some(dir) = &args.out {
            let tris: Vec<f32> = geometry
                .casters
                .iter()
                .flat_map(|t| t.iter().flat_map(|v| v.to_array()))
                .collect();
            let flat: Vec<f32> = rays
                .iter()
                .flat_map(|r| {
                    let mut v = r.origin.to_array().to_vec();
                    v.extend(r.dir.to_array());
                    v.extend([r.t_min, r.t_max]);
                    v
                })
                .collect();
            let bytes = |v: &[f32]| v.iter().flat_map(|x| x.to_le_bytes()).collect::<Vec<u8>>();
            std::fs::write(dir.join(format!("{name}.tris")), bytes(&tris))?;
            std::fs::write(dir.join(format!("{name}.rays")), bytes(&flat))?;
        }
    }
    Ok(())
}
