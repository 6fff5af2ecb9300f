//! `GpuContext::gpu_time`: the device time of the passes a piece of work records.

use crate::common::gpu_for_test;
use glam::Vec3;
use soft_shadow_core::gpu::{GpuRasterizer, GpuTriangles};
use soft_shadow_core::raster::DepthPass;
use soft_shadow_core::{Aabb, GpuContext, Light, View};
use std::time::{Duration, Instant};

/// `passes` depth passes of a 2048² map of a dense grid of triangles, submitted and waited for.
fn depth_passes(ctx: &GpuContext, passes: u32) -> soft_shadow_core::Result<u32> {
    let mut tris = Vec::new();
    for i in 0..64 {
        for j in 0..64 {
            let p = Vec3::new(i as f32 / 32.0 - 1.0, 0.5, j as f32 / 32.0 - 1.0);
            tris.push([p, p + Vec3::X * 0.05, p + Vec3::Z * 0.05]);
        }
    }
    let bounds = Aabb::of_triangles(&tris);
    let light = Light::Point {
        position: Vec3::Y * 3.0,
    };
    let view = View::for_light_center(&light, &soft_shadow_core::Coverage::whole(&bounds));
    let raster = GpuRasterizer::new(ctx);
    let gpu_tris = GpuTriangles::new(ctx, &tris)?;
    let tex = GpuRasterizer::depth_array(ctx, 2048, 1)?;
    for _ in 0..passes {
        let mut enc = ctx.device.create_command_encoder(&Default::default());
        raster.encode_depth_pass(ctx, &mut enc, &gpu_tris, &view, &tex, 0, DepthPass::NEAREST);
        ctx.queue.submit([enc.finish()]);
    }
    ctx.wait()?;
    Ok(passes)
}

#[test]
#[cfg_attr(
    no_gpu_adapter,
    ignore = "needs a GPU adapter: no Vulkan driver found (apt-get install mesa-vulkan-drivers)"
)]
fn device_time_counts_the_passes_and_fits_in_the_wall_time() {
    let Some(ctx) = gpu_for_test("device_time_counts_the_passes_and_fits_in_the_wall_time") else {
        return;
    };
    assert!(ctx.pass_slot().is_none(), "no slot outside gpu_time");
    // Warm-up: pipeline compilation is not part of what is measured below.
    depth_passes(&ctx, 1).unwrap();
    let timed = |passes| {
        let start = Instant::now();
        let (out, device) = ctx.gpu_time(|| depth_passes(&ctx, passes)).unwrap();
        (out, device, start.elapsed())
    };
    let (out, one, wall_one) = timed(1);
    assert_eq!(out, 1, "gpu_time returns the work's output");
    if !ctx.has_timestamps() {
        assert_eq!(one, None, "no timestamps: no device time");
        eprintln!(
            "{}: no TIMESTAMP_QUERY; device time is None",
            ctx.describe()
        );
        return;
    }
    let (_, eight, wall_eight) = timed(8);
    let (one, eight) = (one.unwrap(), eight.unwrap());
    eprintln!(
        "{}: 1 pass {one:?} device / {wall_one:?} wall; 8 passes {eight:?} / {wall_eight:?}",
        ctx.describe()
    );
    assert!(one > Duration::ZERO);
    assert!(
        one <= wall_one && eight <= wall_eight,
        "device time within wall time"
    );
    assert!(
        eight > one * 2,
        "eight passes ({eight:?}) must take more device time than two single ones ({one:?})"
    );
    assert!(ctx.pass_slot().is_none(), "the slot ends with gpu_time");
}
