//! occlusion-slices on the catalogue: the closed form on `plane-occluder` and CPU against GPU
//! (hard cases and the hard-shadow limit: the stability suite, over every technique).

use super::receivers;
use crate::common::{Failures, gpu_for_test};
use glam::Vec3;
use harness::metrics::rms_255;
use occlusion_slices::{OcclusionSlices, Prefilter};
use soft_shadow_core::{DynTechnique, Light, Receivers as Recv, ShadowTechnique, TechniqueInfo};
use soft_shadow_reference::scenes::catalogue::{SCENE_NAMES, build};

/// Section 3.1's closed form for `plane-occluder`: the pyramid from `p` to the square light cut
/// by the occluder's plane is a square; `V` is the fraction of it outside the occluder.
fn plane_occluder_closed_form(light: &Light, p: Vec3) -> f32 {
    let Light::Rect { center, u_half, .. } = *light else {
        unreachable!("plane-occluder has a rect light")
    };
    let (occ_y, occ_half) = (1.0f32, 0.5f32);
    if p.y >= occ_y - 1e-4 {
        return 1.0;
    }
    let s = (occ_y - p.y) / (center.y - p.y);
    let half = u_half.length() * s;
    let (cx, cz) = (
        p.x * (1.0 - s) + center.x * s,
        p.z * (1.0 - s) + center.z * s,
    );
    let overlap = |c: f32| ((c + half).min(occ_half) - (c - half).max(-occ_half)).max(0.0);
    1.0 - overlap(cx) * overlap(cz) / (4.0 * half * half)
}

/// `plane-occluder` at map resolution 512 with the exact (SAT) filter: within 2/255 RMS of the
/// closed form, on both backends, for 4, 8 and 16 slices (section 3.1: exact up to the
/// rasterization of the occluder's outline).
#[test]
fn occlusion_slices_sat_matches_the_closed_form_on_plane_occluder() {
    let ctx = gpu_for_test("occlusion_slices_sat_matches_the_closed_form_on_plane_occluder");
    let spec = build("plane-occluder").unwrap();
    let r = receivers(&spec, 128);
    let recv = Recv {
        positions: &r.positions,
        normals: &r.normals,
    };
    let exact: Vec<f32> = r
        .positions
        .iter()
        .map(|&p| plane_occluder_closed_form(&spec.light, p))
        .collect();
    let penumbra = exact.iter().filter(|v| **v > 0.0 && **v < 1.0).count();
    assert!(penumbra > 500, "only {penumbra} penumbra receivers");
    for slices in [4, 8, 16] {
        let t = OcclusionSlices::new(slices, Prefilter::Sat);
        let backends = crate::common::backends(ctx.as_ref());
        for be in backends {
            let maps = t
                .generate(
                    crate::common::context(be, ctx.as_ref()),
                    &r.geometry,
                    &spec.light,
                    512,
                )
                .unwrap();
            let v = maps.evaluate(ctx.as_ref(), &recv).unwrap();
            let rms = rms_255(&v, &exact);
            println!("plane-occluder sat-{slices} {be:?} at 512: rms {rms:.3}/255");
            assert!(
                rms < 2.0,
                "sat-{slices} {be:?}: rms {rms:.3} against the closed form"
            );
        }
    }
}

/// Every variant, every catalogue scene whose light it models, at
/// [`super::AGREEMENT_RESOLUTIONS`]: `V` agrees between CPU and GPU ([`crate::common::Agreement`]), and where the GPU
/// rasterizes as the CPU does, the binary slices equal but for at most 0.1% of texels
/// (fragments within rounding of a slice plane).
#[test]
#[cfg_attr(
    no_gpu_adapter,
    ignore = "needs a GPU adapter: no Vulkan driver found (apt-get install mesa-vulkan-drivers)"
)]
fn occlusion_slices_agree_between_cpu_and_gpu_on_every_scene() {
    let Some(ctx) = gpu_for_test("occlusion_slices_agree_between_cpu_and_gpu_on_every_scene")
    else {
        return;
    };
    let mut failures = Failures::default();
    // The maps are held to the CPU's where the GPU rasterizes as it does; `V` everywhere.
    let same_raster = crate::common::rasterizes_as_the_cpu(&ctx);
    for name in SCENE_NAMES {
        let spec = build(name).unwrap();
        let r = receivers(&spec, 96);
        let recv = Recv {
            positions: &r.positions,
            normals: &r.normals,
        };
        let mut set = OcclusionSlices::standard_set();
        set.push(OcclusionSlices::new(8, Prefilter::NBuffer).with_thin_fix(true));
        for t in set {
            if !TechniqueInfo::models(&t, spec.light.kind()) {
                continue;
            }
            for res in super::AGREEMENT_RESOLUTIONS {
                let cm = t
                    .generate_cpu(crate::common::cpu(), &r.geometry, &spec.light, res)
                    .unwrap();
                let gm = t.generate_gpu(&ctx, &r.geometry, &spec.light, res).unwrap();
                let gs = gm.first().read_slices(&ctx).unwrap();
                let differ: usize = cm
                    .first()
                    .slices()
                    .iter()
                    .zip(&gs)
                    .map(|(a, b)| a.iter().zip(b).filter(|(x, y)| x != y).count())
                    .sum();
                let frac = differ as f64 / (res * res * t.slices) as f64;
                println!(
                    "{name} {} {res}: {:.3}% of slice texels differ",
                    t.label(),
                    frac * 100.0
                );
                failures.check(!same_raster || frac <= 1e-3, || {
                    format!(
                        "{name} {} {res}: {:.3}% of slice texels differ",
                        t.label(),
                        frac * 100.0
                    )
                });
                let cv = t.evaluate_cpu(&cm, &recv).unwrap();
                let gv = t.evaluate_gpu(&ctx, &gm, &recv).unwrap();
                failures.agree(&format!("{name} {} {res}", t.label()), &cv, &gv);
            }
        }
    }
    failures.assert_none();
}
