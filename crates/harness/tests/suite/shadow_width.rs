//! shadow-width on the catalogue: CPU against GPU, hard cases, convergence to the hard shadow,
//! and the back-face depth option.

use super::receivers;
use harness::baselines::{Filter, ShadowMapBaseline};
use harness::metrics::rms_255;
use harness::scenes::catalogue::{SCENE_NAMES, build};
use shadow_core::gpu::testing::gpu_for_test;
use shadow_core::{Backend, DynTechnique, Receivers as Recv, ShadowTechnique};
use shadow_width::ShadowWidth;

/// Every variant, every catalogue scene, two resolutions: RMS of `V * 255` between CPU and GPU
/// below 1.0, and the width maps themselves equal to within 1e-3 texel on average.
#[test]
fn shadow_width_agrees_between_cpu_and_gpu_on_every_scene() {
    let Some(ctx) = gpu_for_test("shadow_width_agrees_between_cpu_and_gpu_on_every_scene") else {
        return;
    };
    for name in SCENE_NAMES {
        let spec = build(name).unwrap();
        let r = receivers(&spec, 96);
        let recv = Recv {
            positions: &r.positions,
            normals: &r.normals,
        };
        for t in ShadowWidth::standard_set() {
            for res in [64, 256] {
                let cm = t.generate_cpu(&r.geometry, &spec.light, res).unwrap();
                let gm = t.generate_gpu(&ctx, &r.geometry, &spec.light, res).unwrap();
                let gw = gm.read_width(&ctx).unwrap();
                let mean_diff: f64 = cm
                    .width
                    .data()
                    .iter()
                    .zip(gw.data())
                    .map(|(a, b)| (a - b).abs() as f64)
                    .sum::<f64>()
                    / (res * res) as f64;
                assert!(
                    mean_diff < 1e-3,
                    "{name} {} {res}: width maps differ by {mean_diff} texels on average",
                    t.label()
                );
                let cv = shadow_core::ShadowTechnique::evaluate_cpu(&t, &cm, &recv).unwrap();
                let gv = shadow_core::ShadowTechnique::evaluate_gpu(&t, &ctx, &gm, &recv).unwrap();
                let rms = rms_255(&cv, &gv);
                assert!(
                    rms < 1.0,
                    "{name} {} {res}: CPU/GPU rms {rms:.3}",
                    t.label()
                );
            }
        }
    }
}

/// Every hard-case scene, every variant, resolutions 16, 256 and 2048, both backends: no NaN or
/// Inf, `V` in [0, 1].
#[test]
fn shadow_width_hard_cases_stay_finite_and_in_range() {
    let ctx = gpu_for_test("shadow_width_hard_cases_stay_finite_and_in_range");
    let mut backends = vec![Backend::Cpu];
    if ctx.is_some() {
        backends.push(Backend::Gpu);
    }
    for name in SCENE_NAMES {
        let spec = build(name).unwrap();
        if !spec.hard_case {
            continue;
        }
        let r = receivers(&spec, 48);
        let recv = Recv {
            positions: &r.positions,
            normals: &r.normals,
        };
        for t in ShadowWidth::standard_set() {
            for res in [16, 256, 2048] {
                for &be in &backends {
                    let maps = t
                        .generate(be, ctx.as_ref(), &r.geometry, &spec.light, res)
                        .unwrap();
                    let v = t.evaluate(ctx.as_ref(), &maps, &recv).unwrap();
                    assert_eq!(v.len(), r.positions.len());
                    let bad = v
                        .iter()
                        .filter(|x| !(x.is_finite() && (0.0..=1.0).contains(*x)))
                        .count();
                    assert_eq!(bad, 0, "{name} {} {res} {be:?}", t.label());
                }
            }
        }
    }
}

/// On `tiny-light` (a 0.2 mm light) the softness goes to infinity: every variant equals the
/// hard shadow map (same map, same biases) to RMS below 1/255.
#[test]
fn shadow_width_converges_to_the_hard_shadow_on_tiny_light() {
    let spec = build("tiny-light").unwrap();
    let r = receivers(&spec, 96);
    let recv = Recv {
        positions: &r.positions,
        normals: &r.normals,
    };
    let hard = ShadowMapBaseline::new(Filter::Hard);
    for res in [128, 512] {
        let hm = hard
            .generate(Backend::Cpu, None, &r.geometry, &spec.light, res)
            .unwrap();
        let hv = hard.evaluate(None, &hm, &recv).unwrap();
        let shadowed = hv.iter().filter(|v| **v < 0.5).count();
        assert!(
            shadowed > 100,
            "the hard shadow covers {shadowed} receivers"
        );
        for t in ShadowWidth::standard_set() {
            if t.depth != shadow_width::DepthLayer::Front {
                continue;
            }
            let m = t
                .generate(Backend::Cpu, None, &r.geometry, &spec.light, res)
                .unwrap();
            let v = t.evaluate(None, &m, &recv).unwrap();
            let rms = rms_255(&hv, &v);
            assert!(
                rms < 1.0,
                "{} {res}: rms {rms} against the hard shadow",
                t.label()
            );
        }
    }
}
