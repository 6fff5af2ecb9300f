//! shadow-width on the catalogue: CPU against GPU and the back-face depth option (hard cases and
//! the hard-shadow limit: the stability suite, over every technique).

use super::receivers;
use crate::common::gpu_for_test;
use harness::metrics::rms_255;
use harness::scenes::catalogue::{SCENE_NAMES, build};
use shadow_width::{Neighbours, ShadowWidth, WidthMethod};
use soft_shadow_core::{Receivers as Recv, ShadowTechnique};

/// Every standard variant (and the 3- and 6-neighbour propagation on `plane-occluder`), every
/// catalogue scene, two resolutions: RMS of `V * 255` between CPU and GPU
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
        // The paper's 3 and 6 hardware directions (papers only) on the first scene.
        let hardware = [Neighbours::Three, Neighbours::Six]
            .map(|neighbours| ShadowWidth::new(WidthMethod::Propagate { neighbours }));
        let extra = if name == SCENE_NAMES[0] {
            &hardware[..]
        } else {
            &[]
        };
        for t in ShadowWidth::standard_set().iter().chain(extra) {
            for res in super::AGREEMENT_RESOLUTIONS {
                let cm = t
                    .generate_cpu(crate::common::cpu(), &r.geometry, &spec.light, res)
                    .unwrap();
                let gm = t.generate_gpu(&ctx, &r.geometry, &spec.light, res).unwrap();
                let gw = gm.read_width(&ctx).unwrap();
                let mean_diff: f64 = cm
                    .width()
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
                let cv = soft_shadow_core::ShadowTechnique::evaluate_cpu(t, &cm, &recv).unwrap();
                let gv =
                    soft_shadow_core::ShadowTechnique::evaluate_gpu(t, &ctx, &gm, &recv).unwrap();
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
