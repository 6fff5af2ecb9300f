//! One technique on its own, without the ECS or the report: the README's example, compiled.
//!
//! `cargo run --release --example standalone`

use glam::Vec3;
use occlusion_slices::{OcclusionSlices, Prefilter};
use soft_shadow_core::{CpuContext, GpuContext, Light, Receivers, SceneGeometry, ShadowTechnique};

fn main() -> soft_shadow_core::Result<()> {
    // A 1 m square occluder 1 m above a ground plane, a 0.8 m square light 3 m up.
    let quad = |h: f32, y: f32| {
        let p = |x: f32, z: f32| Vec3::new(x, y, z);
        vec![
            [p(-h, -h), p(h, h), p(h, -h)],
            [p(-h, -h), p(-h, h), p(h, h)],
        ]
    };
    let mut casters = quad(0.5, 1.0);
    casters.extend(quad(4.0, 0.0));

    // Receivers along a line on the ground crossing the shadow's edge.
    let points: Vec<Vec3> = (0..=10)
        .map(|i| Vec3::new(0.2 + 0.1 * i as f32, 0.0, 0.0))
        .collect();
    let normals = vec![Vec3::Y; points.len()];
    let receivers = Receivers::new(&points, &normals);

    let geometry = SceneGeometry::new(casters, Vec::new());
    let light = Light::Rect {
        center: Vec3::new(0.0, 3.0, 0.0),
        u_half: Vec3::X * 0.4,
        v_half: Vec3::Z * 0.4,
    };
    let technique = OcclusionSlices::new(8, Prefilter::Sat);
    // Keep one CPU context (its buffer pool, its memory budget) for every generation.
    let cpu = CpuContext::new();
    let maps = technique.generate_cpu(&cpu, &geometry, &light, 1024)?;
    let v_cpu = technique.evaluate_cpu(&maps, &receivers)?;
    println!("x      V (cpu)");
    for (p, v) in points.iter().zip(&v_cpu) {
        println!("{:.2}   {v:.3}", p.x);
    }
    match GpuContext::new() {
        Ok(gpu) => {
            // The GPU path computes the same function:
            let gpu_maps = technique.generate_gpu(&gpu, &geometry, &light, 1024)?;
            let v_gpu = technique.evaluate_gpu(&gpu, &gpu_maps, &receivers)?;
            let worst = v_cpu
                .iter()
                .zip(&v_gpu)
                .map(|(a, b)| (a - b).abs())
                .fold(0.0f32, f32::max);
            println!(
                "GPU ({}): largest |V_cpu - V_gpu| = {worst:.2e}",
                gpu.describe()
            );
        }
        Err(e) => println!("GPU path skipped: {e}"),
    }
    Ok(())
}
