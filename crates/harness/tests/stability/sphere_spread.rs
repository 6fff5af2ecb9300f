//! A sphere lamp's penumbrae keep their width off its views' axes: a sphere shows every receiver
//! its whole disc, while a map's kernel models the disc facing along the view's axis, which a
//! receiver off that axis sees foreshortened (`soft_shadow_core::light_space::sphere_spread`),
//! and accumulation's samples on that disc show it foreshortened too
//! (`soft_shadow_core::Light::map_sample`). On `room-lamp-corner` (a sphere lamp among
//! furniture, its shadows in five cube faces at up to 57 degrees off a face's axis), every
//! technique's default that models a sphere reads the penumbrae 35 degrees and more off a face's
//! axis at most [`OFF_AXIS_SHARPER`] sharper than those near its axis, against the reference,
//! CPU and GPU ([`EXCUSED`] names the one let off).
//!
//! The measure is how much too sharp a penumbra reads: the mean over the reference's penumbra
//! receivers of `(V - V_ref)` signed towards 1/2 (positive: the lit half too light and the dark
//! half too dark), near the axes (cosine above 0.95) and off them (below 0.82). Measured at 512²
//! over a 128² G-buffer, CPU and lavapipe alike: penumbra-limit +4.3 near and +6.2 off,
//! occlusion-slices +8.8 and +13.4 (its square kernel of the ellipse's area is still narrower
//! than the ellipse across it), 16-sample accumulation +3.5 and +3.5 (before its samples lay in
//! the ball, +3.1 and +14.3), shadow-width +36.5 and +35.0 (inner penumbrae only), the hard
//! map +54.3 and +52.9, PCF +33.7 and +32.6; before the spread +5.0 and +11.9, +9.5 and +17.5.

use super::backends;
use harness::setup::PreparedScene;
use soft_shadow_core::{Backend, Context, Light};
use soft_shadow_reference::ground_truth::GroundTruthSettings;
use soft_shadow_reference::scenes::catalogue::build;

/// How much sharper (1/255) the penumbrae off the faces' axes may read than those near them.
const OFF_AXIS_SHARPER: f64 = 5.5;

/// `(technique, worst, why)`: defaults let off, with the measured reason; each may read its
/// penumbrae off the axes at most `worst` sharper than near them (1/255: what it read when the
/// excuse was written, plus 0.5), and fails where it no longer needs the excuse.
const EXCUSED: &[(&str, f64, &str)] = &[(
    "pcss",
    14.9,
    "PCSS as engines ship it: its disc kernels take the light's size in the map's plane, the disc \
     facing the face's axis, which a receiver off the axis sees foreshortened (near the axes \
     -3.8/255, off them +10.6; with square kernels, which read every penumbra too wide, -19.9 \
     and -5.1). Widened by the sphere's spread as the paper techniques' kernels are, it read \
     -4.5 and +3.8, still over the bound, and its image error grew (128² G-buffer: torus \
     2048² 0.975 to 1.047, room-lamp 2048² 0.290 to 0.323, teapot-sphere 2048² 1.325 to \
     1.374; the two rooms and two single views summed 57.6 to 58.0)",
)];

#[test]
fn a_sphere_lamps_penumbrae_keep_their_width_off_its_views_axes() {
    let scene = PreparedScene::new(
        build("room-lamp-corner").unwrap(),
        128,
        GroundTruthSettings::default(),
    )
    .unwrap();
    assert_eq!(scene.views.kind_name(), "cube");
    let Light::Sphere { center, .. } = scene.spec.light else {
        panic!("room-lamp-corner's lamp is a sphere");
    };
    let reference = scene.reference_v();
    // The cosine of each receiver's angle off the axis of the cube face it lies in.
    let cos: Vec<f32> = scene
        .positions
        .iter()
        .map(|p| {
            let d = *p - center;
            d.abs().max_element() / d.length().max(f32::MIN_POSITIVE)
        })
        .collect();
    let registry = soft_shadow_techniques::registry();
    let mut failures = Vec::new();
    for family in registry.families() {
        let t = family.default_variant().clone();
        if !t.models(soft_shadow_core::LightKind::Sphere) {
            continue;
        }
        let family = family.name();
        for backend in backends() {
            let ctx = match backend {
                Backend::Cpu => Context::Cpu(super::common::cpu()),
                Backend::Gpu => Context::Gpu(super::gpu().expect("a GPU backend")),
            };
            let v = t
                .generate_in(ctx, &scene.geometry, &scene.spec.light, &scene.views, 512)
                .and_then(|m| m.evaluate(super::gpu(), &scene.receivers()))
                .unwrap();
            // Mean sharpening of the penumbra receivers whose cosine lies in `range`.
            let sharper = |range: std::ops::Range<f32>| {
                let (mut sum, mut n) = (0.0f64, 0usize);
                for i in 0..v.len() {
                    let r = reference[i];
                    if r > 0.02 && r < 0.98 && range.contains(&cos[i]) {
                        sum += f64::from(v[i] - r) * 255.0 * f64::from((r - 0.5).signum());
                        n += 1;
                    }
                }
                assert!(n > 100, "{family} {backend:?}: {n} penumbra receivers");
                sum / n as f64
            };
            let (near, off) = (sharper(0.95..1.01), sharper(0.0..0.82));
            let what = format!("{family} {} {backend:?}", t.variant());
            println!("{what}: sharper near the axes {near:.2}, off them {off:.2}");
            let excuse = EXCUSED.iter().find(|(name, ..)| *name == family);
            let bound = excuse.map_or(OFF_AXIS_SHARPER, |(_, worst, _)| *worst);
            if off > near + bound {
                failures.push(format!(
                    "{what}: penumbrae off the faces' axes {off:.2}/255 too sharp, near them {near:.2}"
                ));
            } else if excuse.is_some() && off <= near + OFF_AXIS_SHARPER {
                failures.push(format!(
                    "{what}: off the axes {off:.2}, near them {near:.2}: its excuse is no longer needed"
                ));
            }
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}
