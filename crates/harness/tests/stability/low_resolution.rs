//! Maps cover what casts: at 16², on `plane-occluder` and `skewed-triangle` (their shadows cover
//! a few percent of an 8 m ground), every technique that models the scene's light (the report's
//! rows there) still draws a shadow. Its rms must be well below the "no shadow" image's (at most
//! 80% of it) on both backends. With maps fitted to the whole scene, the ground included, every
//! technique returned `V = 1` there (rms 49.55 on `skewed-triangle` for all, exactly the
//! no-shadow image's). The square occluder is an open sheet: shadow-width's `edt-back` measures
//! from its front face, having no back face to use.

use super::common::receivers;
use super::{backends, label, reference, techniques, visibility};
use harness::metrics::rms_255;
use soft_shadow_reference::scenes::catalogue::build;

#[test]
fn every_technique_draws_a_shadow_at_16_texels() {
    let mut failures = Vec::new();
    for name in ["plane-occluder", "skewed-triangle"] {
        let spec = build(name).unwrap();
        let r = receivers(&spec, 48);
        let reference = reference(&spec.light, &r);
        let no_shadow = rms_255(&vec![1.0; reference.len()], &reference);
        for t in techniques() {
            if !t.models(spec.light.kind()) {
                continue;
            }
            let scene = &spec;
            for be in backends() {
                let what = label(t.as_ref(), &scene.name, 16, be);
                let v = visibility(t.as_ref(), be, &r, &scene.light, 16, &what);
                let rms = rms_255(&v, &reference);
                if rms > 0.8 * no_shadow {
                    failures.push(format!("{what}: rms {rms:.2}, no shadow {no_shadow:.2}"));
                }
            }
        }
    }
    assert!(
        failures.is_empty(),
        "no shadow at 16²:\n{}",
        failures.join("\n")
    );
}
