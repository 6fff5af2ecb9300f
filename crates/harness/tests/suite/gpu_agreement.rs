//! GPU against CPU on every catalogue scene: depth maps, G-buffers and every baseline's `V`.
//! With `CI` set a missing adapter fails these tests; elsewhere they skip with one line.

use super::receivers;
use crate::common::{Failures, gpu_for_test};
use shadow_maps::{Filter, SamplePattern, ShadowMapBaseline};
use soft_shadow_core::gpu::{GpuRasterizer, GpuTriangles};
use soft_shadow_core::raster::{DepthPass, depth_map_pass, gbuffer};
use soft_shadow_core::view::NO_OCCLUDER;
use soft_shadow_core::{Receivers as Recv, ShadowTechnique, TechniqueInfo, View};
use soft_shadow_reference::scenes::catalogue::{SCENE_NAMES, build};

/// Texels where the CPU and GPU disagree on coverage (a fragment exactly on an edge after snapping)
/// may be at most this fraction of the map.
const MAX_COVERAGE_MISMATCH: f64 = 1e-3;

/// A covered texel's depth may differ between the backends by this fraction of the view's depth
/// range on at most [`MAX_COVERAGE_MISMATCH`] of the map (where an edge-on face's snapped
/// coverage decides which surface a texel holds): on a GPU that rasterizes as the CPU does
/// ([`crate::common::rasterizes_as_the_cpu`]), and on hardware, which interpolates depth in its
/// own precision (an NVIDIA H200: up to 6.5e-4 on the bunny, on 6% of its covered texels).
const MAX_DEPTH_DIFFERENCE: [f32; 2] = [3e-5, 2e-3];

/// A G-buffer position may differ between the backends by this fraction of the scene's size,
/// likewise (the H200: up to 1.6e-4 on `foliage`).
const MAX_POSITION_DIFFERENCE: [f32; 2] = [1e-5, 1e-3];

/// The bound of `bounds` for `ctx`: the first where it rasterizes as the CPU, else the second.
fn bound(ctx: &soft_shadow_core::GpuContext, bounds: [f32; 2]) -> f32 {
    bounds[usize::from(!crate::common::rasterizes_as_the_cpu(ctx))]
}

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
    let mut failures = Failures::default();
    let max_depth = bound(&ctx, MAX_DEPTH_DIFFERENCE);
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
            let (mut mismatch, mut worst, mut covered, mut far) = (0usize, 0.0f32, 0usize, 0usize);
            for (c, g) in cpu.data().iter().zip(gpu.data()) {
                if (*c == NO_OCCLUDER) != (*g == NO_OCCLUDER) {
                    mismatch += 1;
                } else if *c != NO_OCCLUDER {
                    covered += 1;
                    let d = (c - g).abs() / range;
                    worst = worst.max(d);
                    far += usize::from(d > max_depth);
                }
            }
            println!(
                "{name} {pass:?}: worst depth difference {worst:e} of the range, {far} texels \
                 apart by more than {max_depth:e}, {mismatch} coverage mismatches, \
                 {covered} texels covered"
            );
            let frac = mismatch as f64 / (res * res) as f64;
            failures.check(frac <= MAX_COVERAGE_MISMATCH, || {
                format!("{name} {pass:?}: {mismatch} texels differ in coverage")
            });
            failures.check(far as f64 <= MAX_COVERAGE_MISMATCH * (res * res) as f64, || {
                format!(
                    "{name} {pass:?}: {far} texels' depths differ by more than {max_depth:e} of \
                     the range (up to {worst:e})"
                )
            });
        }
    }
    failures.assert_none();
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
    let mut failures = Failures::default();
    let max_position = bound(&ctx, MAX_POSITION_DIFFERENCE);
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
        // A pixel whose normals differ holds another surface on each backend (two surfaces
        // within the rasterizers' precision of each other's depth): a coverage mismatch.
        let (mut mismatch, mut worst_p) = (0usize, 0.0f32);
        for (c, g) in cpu.data().iter().zip(gpu.data()) {
            if c.covered != g.covered || (c.covered && (c.normal - g.normal).length() > 1e-4) {
                mismatch += 1;
            } else if c.covered {
                worst_p =
                    worst_p.max((c.position - g.position).length() / (scale + c.position.length()));
            }
        }
        println!(
            "{name}: {mismatch} pixels differ in coverage or surface, positions by up to \
             {worst_p:e} of the scene size"
        );
        failures.check(
            mismatch as f64 / (w * h) as f64 <= MAX_COVERAGE_MISMATCH,
            || format!("{name}: {mismatch} pixels differ in coverage or surface"),
        );
        failures.check(worst_p < max_position, || {
            format!("{name}: positions differ by {worst_p:e} of the scene size")
        });
    }
    failures.assert_none();
}

/// Every baseline, both backends, every catalogue scene: `V` agrees between CPU and GPU ([`crate::common::Agreement`]).
#[test]
#[cfg_attr(
    no_gpu_adapter,
    ignore = "needs a GPU adapter: no Vulkan driver found (apt-get install mesa-vulkan-drivers)"
)]
fn baselines_agree_between_cpu_and_gpu_on_every_scene() {
    let Some(ctx) = gpu_for_test("baselines_agree_between_cpu_and_gpu_on_every_scene") else {
        return;
    };
    let mut baselines = ShadowMapBaseline::standard_set(&[16]);
    baselines.push(
        ShadowMapBaseline::new(Filter::Accumulate { samples: 16 })
            .with_pattern(SamplePattern::Rotated),
    );
    let mut failures = Failures::default();
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
                failures.agree(
                    &format!("{name} {} {} {res}", TechniqueInfo::name(b), b.variant()),
                    &cv,
                    &gv,
                );
            }
        }
    }
    failures.assert_none();
}

/// PCSS at 2048², where its search and filter caps are fractions of the map side (64 and 128
/// texels, above the 16 and 32 of the agreement resolutions): both backends read the caps from
/// the same uniform and agree ([`crate::common::Agreement`]) on `contact` and `overlap`.
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
    let mut failures = Failures::default();
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
        failures.agree(&format!("{name} pcss 2048"), &cv, &gv);
    }
    failures.assert_none();
}

/// Every technique, both backends, on the scenes whose lights have several views (cube faces
/// around `room-lamp`'s lamp and `light-plane`'s light, cascades along `street-sun`'s street):
/// `V` agrees between CPU and GPU ([`crate::common::Agreement`]), so each view's maps and the selection of a view per receiver
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
    let mut failures = Failures::default();
    for name in ["room-lamp", "street-sun", "light-plane"] {
        let spec = build(name).unwrap();
        let r = receivers(&spec, 48);
        let recv = Recv {
            positions: &r.positions,
            normals: &r.normals,
        };
        for t in harness::report::all_techniques(true) {
            let models = |k| t.models(k);
            let light = match soft_shadow_reference::scenes::relight::relight(
                &spec.light,
                &r.geometry.bounds,
                models,
            ) {
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
            failures.agree(&format!("{what} ({} views)", views.len()), &cv, &gv);
        }
    }
    failures.assert_none();
}
