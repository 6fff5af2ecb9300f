//! Hard cases: no NaN/Inf, `V` in [0, 1], on both backends, for every baseline.

use super::receivers;
use harness::baselines::{Filter, ShadowMapBaseline};
use harness::metrics::rms_255;
use harness::scenes::catalogue::{SCENE_NAMES, build};
use shadow_core::gpu::testing::gpu_for_test;
use shadow_core::{Backend, DynTechnique, Receivers as Recv};

#[test]
fn hard_cases_stay_finite_and_in_range() {
    let ctx = gpu_for_test("hard_cases_stay_finite_and_in_range");
    let mut backends = vec![Backend::Cpu];
    if ctx.is_some() {
        backends.push(Backend::Gpu);
    }
    let baselines = ShadowMapBaseline::standard_set(&[4]);
    for name in SCENE_NAMES {
        let spec = build(name).unwrap();
        if !spec.hard_case {
            continue;
        }
        let r = receivers(&spec, 64);
        let recv = Recv {
            positions: &r.positions,
            normals: &r.normals,
        };
        for b in &baselines {
            for res in [16, 256, 2048] {
                for &be in &backends {
                    let maps = b
                        .generate(be, ctx.as_ref(), &r.geometry, &spec.light, res)
                        .unwrap();
                    let v = b.evaluate(ctx.as_ref(), &maps, &recv).unwrap();
                    assert_eq!(v.len(), r.positions.len());
                    assert!(
                        v.iter().all(|x| x.is_finite() && (0.0..=1.0).contains(x)),
                        "{name} {} {res} {be:?}",
                        DynTechnique::name(b)
                    );
                }
            }
        }
    }
    assert!(
        SCENE_NAMES
            .iter()
            .filter(|n| build(n).unwrap().hard_case)
            .count()
            >= 8
    );
}

/// On `tiny-light` (a 0.2 mm light) accumulation's samples coincide: it equals the hard shadow map.
#[test]
fn tiny_light_accumulation_equals_the_hard_shadow() {
    let spec = build("tiny-light").unwrap();
    let r = receivers(&spec, 96);
    let recv = Recv {
        positions: &r.positions,
        normals: &r.normals,
    };
    let run = |f| {
        let b = ShadowMapBaseline::new(f);
        let m = b
            .generate(Backend::Cpu, None, &r.geometry, &spec.light, 512)
            .unwrap();
        b.evaluate(None, &m, &recv).unwrap()
    };
    let hard = run(Filter::Hard);
    let acc = run(Filter::Accumulate { samples: 16 });
    let rms = rms_255(&hard, &acc);
    assert!(rms < 1.0, "rms {rms}");
}
