//! GPU against CPU on every catalogue scene: depth maps, G-buffers and every baseline's `V`.
//! With `CI` set a missing adapter fails these tests; elsewhere they skip with one line.

use super::receivers;
use crate::common::gpu_for_test;
use harness::metrics::rms_255;
use harness::scenes::catalogue::{SCENE_NAMES, build};
use shadow_maps::ShadowMapBaseline;
use soft_shadow_core::gpu::{GpuRasterizer, GpuTriangles};
use soft_shadow_core::raster::{DepthPass, depth_map_pass, gbuffer};
use soft_shadow_core::view::NO_OCCLUDER;
use soft_shadow_core::{Receivers as Recv, ShadowTechnique, TechniqueInfo, View};

/// Texels where the CPU and GPU disagree on coverage (a fragment exactly on an edge after snapping)
/// may be at most this fraction of the map.
const MAX_COVERAGE_MISMATCH: f64 = 1e-3;

/// Every depth pass (nearest, farthest, nearest and farthest back face) on every catalogue scene: CPU and GPU
/// agree on coverage (culling included) and depth.
#[test]
#[cfg_attr(
    no_gpu_adapter,
    ignore = "needs a GPU adapter: no Vulkan driver found (apt-get install mesa-vulkan-drivers)"
)]
fn gpu_depth_maps_match_the_cpu_rasterizer() {
    let Some(ctx) = gpu_for_test("gpu_depth_maps_match_the_cpu_rasterizer") else {
        return;
    };
    let raster = GpuRasterizer::new(&ctx);
    let passes = [
        DepthPass::NEAREST,
        DepthPass::FARTHEST,
        DepthPass::NEAREST_BACK,
        DepthPass::FARTHEST_BACK,
    ];
    for name in SCENE_NAMES {
        let spec = build(name).unwrap();
        let geo = spec.to_scene().unwrap().geometry();
        let view = View::for_light_center(
            &spec.light,
            &soft_shadow_core::Coverage::new(&geo, &spec.light),
        );
        let res = 256;
        let tris = GpuTriangles::new(&ctx, &geo.casters).unwrap();
        for pass in passes {
            let cpu = depth_map_pass(
                &soft_shadow_core::pool::Pool::new(0).into(),
                &view,
                res,
                &geo.casters,
                pass,
            );
            let tex = GpuRasterizer::depth_array(&ctx, res, 1).unwrap();
            let mut enc = ctx.device.create_command_encoder(&Default::default());
            raster.encode_depth_pass(&ctx, &mut enc, &tris, &view, &tex, 0, pass);
            ctx.queue.submit([enc.finish()]);
            let gpu = GpuRasterizer::read_depth_pass(&ctx, &tex, 0, &view, pass).unwrap();
            let range = view.far - view.near;
            let (mut mismatch, mut worst, mut covered) = (0usize, 0.0f32, 0usize);
            for (c, g) in cpu.data().iter().zip(gpu.data()) {
                if (*c == NO_OCCLUDER) != (*g == NO_OCCLUDER) {
                    mismatch += 1;
                } else if *c != NO_OCCLUDER {
                    covered += 1;
                    worst = worst.max((c - g).abs() / range);
                }
            }
            eprintln!(
                "{name} {pass:?}: worst depth difference {worst:e} of the range, \
                 {mismatch} coverage mismatches, {covered} texels covered"
            );
            let frac = mismatch as f64 / (res * res) as f64;
            assert!(
                frac <= MAX_COVERAGE_MISMATCH,
                "{name} {pass:?}: {mismatch} texels differ in coverage"
            );
            assert!(
                worst < 3e-5,
                "{name} {pass:?}: depth differs by {worst:e} of the range"
            );
        }
    }
}

#[test]
#[cfg_attr(
    no_gpu_adapter,
    ignore = "needs a GPU adapter: no Vulkan driver found (apt-get install mesa-vulkan-drivers)"
)]
fn gpu_gbuffer_matches_the_cpu_rasterizer() {
    let Some(ctx) = gpu_for_test("gpu_gbuffer_matches_the_cpu_rasterizer") else {
        return;
    };
    let raster = GpuRasterizer::new(&ctx);
    for name in SCENE_NAMES {
        let spec = build(name).unwrap();
        let geo = spec.to_scene().unwrap().geometry();
        let (w, h) = (160, 120);
        let view = spec.camera.view(w, h);
        let cpu = gbuffer(
            &soft_shadow_core::pool::Pool::new(0).into(),
            &view,
            spec.camera.eye,
            w,
            h,
            &geo.receivers,
        );
        let gpu = raster
            .gbuffer(&ctx, &geo.receivers, &view, spec.camera.eye, w, h)
            .unwrap();
        let scale = geo.bounds.diagonal();
        let (mut mismatch, mut worst_p, mut worst_n) = (0usize, 0.0f32, 0.0f32);
        for (c, g) in cpu.data().iter().zip(gpu.data()) {
            if c.covered != g.covered {
                mismatch += 1;
            } else if c.covered {
                worst_p =
                    worst_p.max((c.position - g.position).length() / (scale + c.position.length()));
                worst_n = worst_n.max((c.normal - g.normal).length());
            }
        }
        assert!(
            mismatch as f64 / (w * h) as f64 <= MAX_COVERAGE_MISMATCH,
            "{name}: {mismatch} pixels differ in coverage"
        );
        assert!(
            worst_p < 1e-5,
            "{name}: positions differ by {worst_p:e} of the scene size"
        );
        assert!(worst_n < 1e-4, "{name}: normals differ by {worst_n:e}");
    }
}

/// Every baseline, both backends, every catalogue scene: RMS of `V * 255` below 1.0.
#[test]
#[cfg_attr(
    no_gpu_adapter,
    ignore = "needs a GPU adapter: no Vulkan driver found (apt-get install mesa-vulkan-drivers)"
)]
fn baselines_agree_between_cpu_and_gpu_on_every_scene() {
    let Some(ctx) = gpu_for_test("baselines_agree_between_cpu_and_gpu_on_every_scene") else {
        return;
    };
    let baselines = ShadowMapBaseline::standard_set(&[16]);
    for name in SCENE_NAMES {
        let spec = build(name).unwrap();
        let r = receivers(&spec, 96);
        let recv = Recv {
            positions: &r.positions,
            normals: &r.normals,
        };
        for b in &baselines {
            for res in super::AGREEMENT_RESOLUTIONS {
                let cm = b
                    .generate_cpu(crate::common::cpu(), &r.geometry, &spec.light, res)
                    .unwrap();
                let gm = b.generate_gpu(&ctx, &r.geometry, &spec.light, res).unwrap();
                let cv = b.evaluate_cpu(&cm, &recv).unwrap();
                let gv = b.evaluate_gpu(&ctx, &gm, &recv).unwrap();
                let rms = rms_255(&cv, &gv);
                assert!(
                    rms < 1.0,
                    "{name} {} {res}: CPU/GPU rms {rms:.3}",
                    TechniqueInfo::name(b)
                );
            }
        }
    }
}

/// PCSS at 2048², where its search and filter caps are fractions of the map side (64 and 128
/// texels, above the 16 and 32 of the agreement resolutions): both backends read the caps from
/// the same uniform and agree, RMS of `V * 255` below 1.0, on `contact` and `overlap`.
#[test]
#[cfg_attr(
    no_gpu_adapter,
    ignore = "needs a GPU adapter: no Vulkan driver found (apt-get install mesa-vulkan-drivers)"
)]
fn pcss_caps_agree_between_cpu_and_gpu_at_2048() {
    let Some(ctx) = gpu_for_test("pcss_caps_agree_between_cpu_and_gpu_at_2048") else {
        return;
    };
    let pcss = ShadowMapBaseline::new(shadow_maps::Filter::Pcss);
    for name in ["contact", "overlap"] {
        let spec = build(name).unwrap();
        let r = receivers(&spec, 96);
        let recv = Recv {
            positions: &r.positions,
            normals: &r.normals,
        };
        let cm = pcss
            .generate_cpu(crate::common::cpu(), &r.geometry, &spec.light, 2048)
            .unwrap();
        let gm = pcss
            .generate_gpu(&ctx, &r.geometry, &spec.light, 2048)
            .unwrap();
        let cv = pcss.evaluate_cpu(&cm, &recv).unwrap();
        let gv = pcss.evaluate_gpu(&ctx, &gm, &recv).unwrap();
        let rms = rms_255(&cv, &gv);
        println!("{name} pcss 2048: CPU/GPU rms {rms:.4}");
        assert!(rms < 1.0, "{name} pcss 2048: CPU/GPU rms {rms:.3}");
    }
}

/// Every technique, both backends, on the scenes whose lights have several views (cube faces
/// around `room-lamp`'s lamp and `light-plane`'s light, cascades along `street-sun`'s street):
/// RMS of `V * 255` below 1.0, so each view's maps and the selection of a view per receiver
/// (`views.rs` and `views.wgsl`) agree. A technique that does not model a scene's light runs
/// under the light recast as one it models.
#[test]
#[cfg_attr(
    no_gpu_adapter,
    ignore = "needs a GPU adapter: no Vulkan driver found (apt-get install mesa-vulkan-drivers)"
)]
fn every_technique_agrees_between_cpu_and_gpu_over_several_views() {
    let test = "every_technique_agrees_between_cpu_and_gpu_over_several_views";
    let Some(ctx) = gpu_for_test(test) else {
        return;
    };
    for name in ["room-lamp", "street-sun", "light-plane"] {
        let spec = build(name).unwrap();
        let r = receivers(&spec, 48);
        let recv = Recv {
            positions: &r.positions,
            normals: &r.normals,
        };
        for t in harness::report::all_techniques(true) {
            let models = |k| t.models(k);
            let light =
                match harness::scenes::relight::relight(&spec.light, &r.geometry.bounds, models) {
                    _ if t.models(spec.light.kind()) => spec.light,
                    Some(l) => l,
                    None => continue,
                };
            let views = r.views(&light);
            assert!(views.len() > 1 || light != spec.light, "{name}: one view");
            let res = 128;
            let what = format!("{name} {} {} {res}", t.name(), t.variant());
            let cpu = soft_shadow_core::Context::Cpu(crate::common::cpu());
            let cv = t
                .generate_in(cpu, &r.geometry, &light, &views, res)
                .and_then(|m| m.evaluate(None, &recv))
                .unwrap_or_else(|e| panic!("{what}: {e}"));
            let gv = t
                .generate_in(
                    soft_shadow_core::Context::Gpu(&ctx),
                    &r.geometry,
                    &light,
                    &views,
                    res,
                )
                .and_then(|m| m.evaluate(Some(&ctx), &recv))
                .unwrap_or_else(|e| panic!("{what}: {e}"));
            let rms = rms_255(&cv, &gv);
            println!("{what} ({} views): CPU/GPU rms {rms:.4}", views.len());
            assert!(rms < 1.0, "{what}: CPU/GPU rms {rms:.3}");
        }
    }
}
