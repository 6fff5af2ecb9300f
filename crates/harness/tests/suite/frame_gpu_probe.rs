//! The GPU frame's missing shadows (`shadow_frame::gpu_probe`): every lamp's `V` at the frame's
//! sampled receivers, read back a frame late without waiting, weighs its share of the budget as
//! its own `V` does on the CPU. On lavapipe in CI.

use crate::common::gpu_for_test;
use crate::frame_gpu_timing::GpuStreet;
use shadow_frame::budget::{NO_SHADOW_255, missing_shadow_255};
use shadow_frame::scene::LightSource;
use shadow_frame::{FrameReceivers, FrameSettings, LightState, ShadowConfig, ShadowProbe};
use soft_shadow_core::Receivers;
use std::sync::Arc;

/// The night street on the GPU, its receivers not evaluated, 6 still frames (calibrating off):
/// without a `ShadowProbe` no lamp's share measured its missing shadow (each counts the
/// catalogue's median); with one, every lamp with maps has, and it equals
/// `missing_shadow_255` of its maps' `V` evaluated at the frame's receivers (within 1%, or the
/// last share's value within the budget's hysteresis band where the share kept it).
#[test]
#[cfg_attr(
    no_gpu_adapter,
    ignore = "needs a GPU adapter: no Vulkan driver found (apt-get install mesa-vulkan-drivers)"
)]
fn the_gpu_frame_measures_its_lights_missing_shadows() {
    let Some(ctx) = gpu_for_test("the_gpu_frame_measures_its_lights_missing_shadows") else {
        return;
    };
    let gpu = Arc::new(ctx);
    let street = |probe: bool| {
        let mut s = GpuStreet::new(gpu.clone(), (96, 54), 40.0);
        let world = &mut s.lamps.scene.world;
        world.insert_resource(
            FrameSettings::default()
                .with_evaluate_receivers(false)
                .with_calibrating(false),
        );
        if probe {
            world.insert_resource(ShadowProbe::default());
        }
        for _ in 0..6 {
            s.frame(0);
        }
        s
    };
    let measured = |s: &GpuStreet| -> Vec<(bevy_ecs::entity::Entity, Option<f64>)> {
        s.lamps
            .lamps
            .iter()
            .filter_map(|&e| {
                let state = s.lamps.scene.world.get::<LightState>(e)?;
                let share = state.share?;
                state.maps.as_ref()?;
                Some((e, share.missing_255))
            })
            .collect()
    };
    let unprobed = street(false);
    let without = measured(&unprobed);
    assert!(!without.is_empty());
    assert!(
        without.iter().all(|(_, m)| m.is_none()),
        "without a probe nothing is measured: {without:?}"
    );
    let probed = street(true);
    let with = measured(&probed);
    let world = &probed.lamps.scene.world;
    let frame = world.resource::<FrameReceivers>();
    let receivers = Receivers::new(&frame.positions, &frame.normals);
    let mut checked = 0;
    for (e, m) in &with {
        let state = world.get::<LightState>(*e).unwrap();
        let light = world.get::<LightSource>(*e).unwrap().0;
        let config = world.get::<ShadowConfig>(*e).unwrap();
        let v = state
            .maps
            .as_ref()
            .unwrap()
            .evaluate(Some(&gpu), &receivers)
            .unwrap();
        let want = missing_shadow_255(&light, config, frame, &v).unwrap_or(NO_SHADOW_255);
        let got = m.expect("a lamp with maps has its missing shadow measured");
        println!("lamp {e:?}: missing shadow {got:.2}/255 measured, {want:.2} from its V");
        assert!(
            (got - want).abs() <= 0.01 * want + 1e-3
                || (got.max(1.0) <= want.max(1.0) * shadow_frame::budget::SHARE_HYSTERESIS
                    && want.max(1.0) <= got.max(1.0) * shadow_frame::budget::SHARE_HYSTERESIS),
            "{got} against {want}"
        );
        checked += 1;
    }
    assert!(checked >= 2, "{checked} lamps measured");
}

/// A probe measures the sampled receivers only (every other one of 8192 here); where none of
/// them is lit, the missing shadow is not measured (`None`: the light takes the catalogue's
/// median), never the 0 of the unsampled receivers read as lit. Where they are, it is their rms.
#[test]
fn a_probe_measures_only_the_receivers_it_sampled() {
    use glam::Vec3;
    let n = 8192;
    let light = soft_shadow_core::Light::Point {
        position: Vec3::new(0.0, 2.0, 0.0),
    };
    let config = ShadowConfig::shared();
    let positions: Vec<Vec3> = (0..n)
        .map(|i| Vec3::new((i % 64) as f32 * 0.01, 0.0, (i / 64) as f32 * 0.01))
        .collect();
    // The sampled receivers (even indices) face away from the light, the others face it.
    let normals: Vec<Vec3> = (0..n)
        .map(|i| if i % 2 == 0 { Vec3::NEG_Y } else { Vec3::Y })
        .collect();
    let frame = FrameReceivers {
        positions,
        normals,
        camera: None,
    };
    assert_eq!(FrameReceivers::sample_step(n), 2);
    let probed: Vec<f32> = (0..n)
        .map(|i| if i % 2 == 0 { 0.0 } else { f32::NAN })
        .collect();
    assert_eq!(missing_shadow_255(&light, &config, &frame, &probed), None);
    // Lit sampled receivers, half of them in shadow.
    let mut frame = frame;
    frame.normals = vec![Vec3::Y; n];
    let probed: Vec<f32> = (0..n)
        .map(|i| match i % 4 {
            0 => 0.0,
            2 => 1.0,
            _ => f32::NAN,
        })
        .collect();
    let m = missing_shadow_255(&light, &config, &frame, &probed).unwrap();
    assert!(m > 100.0 && m.is_finite(), "{m}");
}
