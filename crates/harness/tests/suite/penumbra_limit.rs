//! penumbra-limit on the catalogue: CPU against GPU (maps and visibility), hard cases, and the
//! hard-shadow limit.

use super::receivers;
use harness::baselines::{Filter, ShadowMapBaseline};
use harness::metrics::rms_255;
use harness::scenes::catalogue::{SCENE_NAMES, build};
use penumbra_limit::{PenumbraLimit, Storage};
use shadow_core::gpu::testing::gpu_for_test;
use shadow_core::{Backend, DynTechnique, Receivers as Recv, ShadowTechnique};

/// Every variant, every catalogue scene whose light it models, two resolutions: RMS of
/// `V * 255` between CPU and GPU below 1.0, and the stored maps equal up to rasterization
/// differences: at most 1% of texels differ in any channel by more than one storage step.
#[test]
fn penumbra_limit_agrees_between_cpu_and_gpu_on_every_scene() {
    let Some(ctx) = gpu_for_test("penumbra_limit_agrees_between_cpu_and_gpu_on_every_scene") else {
        return;
    };
    for name in SCENE_NAMES {
        let spec = build(name).unwrap();
        let r = receivers(&spec, 96);
        let recv = Recv {
            positions: &r.positions,
            normals: &r.normals,
        };
        for t in PenumbraLimit::standard_set() {
            if !ShadowTechnique::models(&t, spec.light.kind()) {
                continue;
            }
            for res in [64, 256] {
                let cm = t.generate_cpu(&r.geometry, &spec.light, res).unwrap();
                let gm = t.generate_gpu(&ctx, &r.geometry, &spec.light, res).unwrap();
                let gmap = gm.read_map(&ctx).unwrap();
                let step = match t.storage {
                    Storage::F32 => 1e-4,
                    Storage::F16 => 2.0 / 2048.0,
                    Storage::Rgba8 => 1.5 / 255.0,
                };
                let differ = cm
                    .map
                    .data()
                    .iter()
                    .zip(gmap.data())
                    .filter(|(a, b)| {
                        [(a.c, b.c), (a.g, b.g), (a.b, b.b), (a.p / 4.0, b.p / 4.0)]
                            .iter()
                            .any(|(x, y)| (x - y).abs() > step)
                    })
                    .count();
                let frac = differ as f64 / (res * res) as f64;
                assert!(
                    frac <= 0.01,
                    "{name} {} {res}: {:.2}% of texels differ",
                    t.label(),
                    frac * 100.0
                );
                let cv = t.evaluate_cpu(&cm, &recv).unwrap();
                let gv = t.evaluate_gpu(&ctx, &gm, &recv).unwrap();
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
fn penumbra_limit_hard_cases_stay_finite_and_in_range() {
    let ctx = gpu_for_test("penumbra_limit_hard_cases_stay_finite_and_in_range");
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
        for t in PenumbraLimit::standard_set() {
            if !ShadowTechnique::models(&t, spec.light.kind()) {
                continue;
            }
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

/// On `tiny-light` (a 0.2 mm light) the penumbra vanishes: every variant is the hard shadow
/// map to RMS below 4/255 (they differ only on the antialiased texel along the edge).
#[test]
fn penumbra_limit_converges_to_the_hard_shadow_on_tiny_light() {
    let spec = build("tiny-light").unwrap();
    let r = receivers(&spec, 96);
    let recv = Recv {
        positions: &r.positions,
        normals: &r.normals,
    };
    let hard = ShadowMapBaseline::new(Filter::Hard);
    let res = 512;
    let hm = hard
        .generate(Backend::Cpu, None, &r.geometry, &spec.light, res)
        .unwrap();
    let hv = hard.evaluate(None, &hm, &recv).unwrap();
    for t in PenumbraLimit::standard_set() {
        let m = t.generate_cpu(&r.geometry, &spec.light, res).unwrap();
        let v = t.evaluate_cpu(&m, &recv).unwrap();
        let rms = rms_255(&v, &hv);
        assert!(
            rms < 4.0,
            "{}: rms {rms:.2} against the hard shadow",
            t.label()
        );
    }
}
