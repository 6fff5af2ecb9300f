//! `tiny-light`: as the light shrinks to 0.2 mm, every technique converges to the hard shadow.
//!
//! On `plane-occluder`'s layout with the rect light's half side 0.2 m, 0.02 m and 0.1 mm (the
//! `tiny-light` scene), each technique's `V` is compared with the exact hard shadow of a point
//! light at the light's centre (one ray per receiver). With the 0.1 mm light its error must be at
//! most [`TOLERANCE_255`], the texel aliasing of a 1024² map along the shadow's edge (a hard
//! shadow map is 8.3 away), and no more than with the 0.2 m light (12-21 away for every
//! technique that draws that penumbra). The error need not fall monotonically: a slightly soft
//! edge (0.02 m) can sit closer in RMS to the exact edge than an aliased hard one.
//!
//! The square occluder is one open sheet: shadow-width's back-face variant (`edt-back`), whose
//! depth layer is the casters' nearest back faces, has none here and measures from the sheet's
//! front face instead, so it converges like the others. PCF's
//! kernel is fixed in texels, not tied to the light, but since maps cover the casters and the
//! penumbra the light can throw (`soft_shadow_core::Coverage`), its texels shrink with the light and
//! it meets the same bounds (3.3, 1.7, 2.6 here).

use super::common::receivers;
use super::{backends, label, scene_for, techniques, visibility};
use harness::metrics::rms_255;
use soft_shadow_core::LightPoint;
use soft_shadow_reference::ground_truth::RayTracer;
use soft_shadow_reference::scenes::catalogue::{build, plane_occluder};

/// Half sides of the light, largest first; the last is `tiny-light`'s.
const HALF_SIDES: [f32; 3] = [0.2, 0.02, 1e-4];

/// Map resolution.
const RESOLUTION: u32 = 1024;

/// Largest RMS (on `V * 255`) against the hard shadow with the 0.1 mm light.
const TOLERANCE_255: f64 = 10.0;

#[test]
fn the_catalogue_tiny_light_is_the_smallest_size() {
    let tiny = build("tiny-light").unwrap();
    assert_eq!(tiny.light, plane_occluder(HALF_SIDES[2]).light);
}

#[test]
fn every_technique_converges_to_the_hard_shadow() {
    let mut failures = Vec::new();
    for t in techniques() {
        for be in backends() {
            let mut errors = Vec::new();
            for half in HALF_SIDES {
                let scene = scene_for(t.as_ref(), &plane_occluder(half));
                let r = receivers(&scene, 64);
                let LightPoint::Position(center) = scene.light.center() else {
                    unreachable!("plane-occluder's light has a position")
                };
                let tracer = RayTracer::new(&r.geometry.casters);
                let hard: Vec<f32> = r
                    .positions
                    .iter()
                    .zip(&r.normals)
                    .map(|(p, n)| {
                        if tracer.sees(*p, *n, LightPoint::Position(center)) {
                            1.0
                        } else {
                            0.0
                        }
                    })
                    .collect();
                let what = label(t.as_ref(), &scene.name, RESOLUTION, be);
                let v = visibility(t.as_ref(), be, &r, &scene.light, RESOLUTION, &what);
                errors.push(rms_255(&v, &hard));
            }
            let what = format!("{} {} {}", t.name(), t.variant(), be.name());
            eprintln!("{what}: rms vs hard shadow {errors:.2?} for half sides {HALF_SIDES:?}");
            if errors[2] > errors[0] {
                failures.push(format!(
                    "{what}: further from the hard shadow with the 0.1 mm light than with the \
                     0.2 m one: {errors:.2?}"
                ));
            }
            if errors[2] > TOLERANCE_255 {
                failures.push(format!(
                    "{what}: {:.2} from the hard shadow with the 0.1 mm light",
                    errors[2]
                ));
            }
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}
