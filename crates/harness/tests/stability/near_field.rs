//! The sun over a street keeps its near shadows: on `street-sun` (100 blocks over 200 m, the
//! real sun, an eye-height camera), the `V` error of the receivers within 15 m of the camera is
//! within 1.3 times that of the same camera with only the casters within 20 m (one view fitted
//! to them), at 512² and 2048², for every technique that models a distant light. One map over
//! everything in view made it 2-3 times that (`LightViews::single`, reported beside).

use super::techniques;
use harness::setup::PreparedScene;
use soft_shadow_core::{Aabb, Context, LightViews};
use soft_shadow_reference::ground_truth::GroundTruthSettings;
use soft_shadow_reference::scenes::catalogue::build;

#[test]
fn a_street_keeps_its_near_shadows_under_the_sun() {
    let full = build("street-sun").unwrap();
    let mut near = full.clone();
    near.name = "street-sun near casters".into();
    let eye = full.camera.eye;
    near.meshes.retain(|m| {
        let tris: Vec<_> = m.mesh.world_triangles(m.transform).collect();
        !m.caster || (Aabb::of_triangles(&tris).center() - eye).length() < 20.0
    });
    let settings = GroundTruthSettings::default();
    let (full, near) = (
        PreparedScene::new(full, 64, settings).unwrap(),
        PreparedScene::new(near, 64, settings).unwrap(),
    );
    assert_eq!(full.views.kind_name(), "cascades");
    let cpu = Context::Cpu(super::common::cpu());
    let mut failures = Vec::new();
    let mut checked = 0;
    for t in techniques() {
        if !t.models(full.spec.light.kind()) {
            continue;
        }
        for res in [512, 2048] {
            let near_v = |p: &PreparedScene, views: &LightViews| {
                let v = t
                    .generate_in(cpu, &p.geometry, &p.spec.light, views, res)
                    .and_then(|m| m.evaluate(None, &p.receivers()))
                    .unwrap();
                harness::metrics::errors(&v, &p.reference_v(), &p.shading)
                    .classes
                    .near
                    .rms_255
            };
            let (got, alone, one) = (
                near_v(&full, &full.views),
                near_v(&near, &near.views),
                near_v(&full, &LightViews::single()),
            );
            let what = format!("{} {} {res}", t.name(), t.variant());
            println!(
                "{what}: near V rms {got:.2}, near casters alone {alone:.2}, one view {one:.2}"
            );
            checked += 1;
            if got > 1.3 * alone {
                failures.push(format!("{what}: {got:.2} against {alone:.2} alone"));
            }
        }
    }
    assert!(checked >= 20, "{checked} configurations");
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}
