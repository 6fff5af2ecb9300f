//! The calibration: medians of what the frames measured over what the profile predicted.

use crate::calibration::CALIBRATION_FRAMES;
use crate::{Calibration, CoreStats, FrameStats, LightStats};
use bevy_ecs::entity::Entity;

/// A light that made its maps (when `generated`) and evaluated, measured at `factor` times the
/// profile's predictions of 2 ms and 3 ms.
fn light(technique: &str, generated: bool, factor: f64) -> LightStats {
    let (g, e) = (2.0, 3.0);
    LightStats {
        light: Entity::PLACEHOLDER,
        technique: technique.into(),
        resolution: 128,
        views_generated: usize::from(generated),
        receivers_evaluated: 100,
        ms: 0.0,
        generate_ms: if generated { g * factor } else { 0.0 },
        evaluate_ms: e * factor,
        profile_ms: Some([g, e]),
        predicted_ms: Some(g + e),
        budget_ms: Some(10.0),
        waited: false,
    }
}

fn frame(n: u64, core_ms: f64, lights: Vec<LightStats>) -> FrameStats {
    FrameStats {
        frame: n,
        core: CoreStats {
            track_ms: core_ms,
            ..Default::default()
        },
        lights,
        ..Default::default()
    }
}

/// The first frame (every map allocated) is left out; then generation and evaluation measured
/// at 2x their predictions calibrate to 2, once three frames agree (before that the profile's
/// own 1 holds the median).
#[test]
fn measured_twice_the_prediction_calibrates_to_two() {
    let mut c = Calibration::default();
    c.update(&frame(1, 9.0, vec![light("pcss 7x7-9x9", true, 5.0)]), true);
    assert_eq!(c, Calibration::default());
    c.update(&frame(2, 1.0, vec![light("pcss 7x7-9x9", true, 2.0)]), true);
    assert_eq!(
        (c.generate, c.evaluate),
        (1.0, 1.0),
        "one frame moves nothing"
    );
    c.update(&frame(3, 1.0, vec![light("pcss 7x7-9x9", true, 2.0)]), true);
    assert!(
        (c.generate - 2.0).abs() < 1e-12 && (c.evaluate - 2.0).abs() < 1e-12,
        "{c:?}"
    );
    assert_eq!(c.core_ms, 1.0);
}

/// One slow generation among many moves nothing, and a configuration the profile misjudges
/// keeps its own factor: the others, and those never measured, keep the common one.
#[test]
fn one_configuration_keeps_its_own_factor() {
    let mut c = Calibration::default();
    for n in 2..12 {
        c.update(
            &frame(
                n,
                1.0,
                vec![
                    light("pcss 7x7-9x9", true, 1.5),
                    light("pcss 7x7-9x9", true, 1.5),
                    light("occlusion-slices sat-4", n % 3 == 0, 4.0),
                ],
            ),
            true,
        );
    }
    assert!((c.generate - 1.5).abs() < 1e-12, "{c:?}");
    assert!((c.generate_for("pcss", "7x7-9x9") - 1.5).abs() < 1e-12);
    assert!((c.generate_for("occlusion-slices", "sat-4") - 4.0).abs() < 1e-12);
    assert!((c.generate_for("shadow-width", "edt") - 1.5).abs() < 1e-12);
    // A frame that makes no map leaves generation as it was; evaluation follows every frame.
    let before = c.generate;
    for n in 12..12 + CALIBRATION_FRAMES as u64 {
        c.update(
            &frame(n, 1.0, vec![light("pcss 7x7-9x9", false, 3.0)]),
            true,
        );
    }
    assert_eq!(c.generate, before);
    assert!((c.evaluate - 3.0).abs() < 1e-12, "{c:?}");
}

/// The pipeline's own time kept back is the most of the last frames: a frame that shares the
/// budget again (slower) is kept for as many frames, then drops out.
#[test]
fn the_pipelines_time_is_the_most_of_the_last_frames() {
    let mut c = Calibration::default();
    c.update(&frame(2, 3.0, Vec::new()), true);
    for n in 3..3 + CALIBRATION_FRAMES as u64 - 1 {
        c.update(&frame(n, 0.5, Vec::new()), true);
        assert_eq!(c.core_ms, 3.0);
    }
    c.update(&frame(99, 0.5, Vec::new()), true);
    assert_eq!(c.core_ms, 0.5);
    // A GPU frame that reads nothing back times only its recording: its lights calibrate
    // nothing, its pipeline time still counts.
    let slow = || vec![light("pcss 7x7-9x9", true, 9.0)];
    let mut gpu = Calibration::default();
    for n in 2..6 {
        gpu.update(&frame(n, 0.7, slow()), false);
    }
    assert_eq!((gpu.generate, gpu.evaluate, gpu.core_ms), (1.0, 1.0, 0.7));
    // Lights without a profile's prediction (their own technique) calibrate nothing.
    let mut own = light("pcss 7x7-9x9", true, 9.0);
    own.profile_ms = None;
    for n in 2..6 {
        c.update(&frame(n, 0.5, vec![own.clone()]), true);
    }
    assert_eq!((c.generate, c.evaluate), (1.0, 1.0));
}

/// A configuration whose own factor moved counts as drift, as the common ones do; a
/// calibration given by hand is held to what the frames could measure.
#[test]
fn drift_sees_one_configurations_factor_and_new_is_held_in_range() {
    let mut c = Calibration::default();
    for n in 2..8 {
        c.update(
            &frame(
                n,
                0.5,
                vec![
                    light("pcss 7x7-9x9", true, 1.0),
                    light("pcss 7x7-9x9", true, 1.0),
                    light("occlusion-slices sat-4", true, 4.0),
                ],
            ),
            true,
        );
    }
    assert!((c.generate - 1.0).abs() < 1e-12, "{c:?}");
    let drift = c.drift(&Calibration::default());
    assert!((drift - 4.0).abs() < 1e-12, "{drift}");
    let hand = Calibration::new(0.0, f64::NAN, -1.0);
    assert_eq!(
        (hand.generate, hand.evaluate, hand.core_ms),
        (1.0 / crate::calibration::CALIBRATION_MAX_FACTOR, 1.0, 0.0)
    );
}

/// On the device each light's `V` pass is timed on its own ([`Calibration::update_gpu`]): two
/// configurations whose passes run 2x and 300x their CPU rows' predictions calibrate to 2 and
/// 300 each (beyond the CPU's clamp of 16), the global factor their frames' total. Predictions
/// under the CPU's 0.1 ms floor count (timestamps carry no clock overhead). The CPU's frames,
/// timed together, leave every configuration at the global factor, and one such frame after
/// device times puts them back on it.
#[test]
fn device_times_calibrate_each_configurations_evaluation() {
    let small = |technique: &str, factor: f64| LightStats {
        profile_ms: Some([0.02, 0.03]),
        generate_ms: 0.02 * factor,
        evaluate_ms: 0.03 * factor,
        ..light(technique, true, factor)
    };
    let mut c = Calibration::default();
    for _ in 0..3 {
        c.update_gpu(&[small("pcss 7x7-9x9", 2.0), small("pcf r2", 300.0)]);
    }
    let near = |a: f64, b: f64| (a - b).abs() < 1e-9 * b;
    assert!(near(c.evaluate_for("pcss", "7x7-9x9"), 2.0), "{c:?}");
    assert!(near(c.evaluate_for("pcf", "r2"), 300.0), "{c:?}");
    assert!(near(c.evaluate, 302.0 / 2.0), "{c:?}");
    assert!(near(c.generate_for("pcf", "r2"), 300.0), "{c:?}");
    assert_eq!(c.evaluate_for("hard-shadow-map", "nearest"), c.evaluate);
    // Evaluations timed together again (the receivers evaluated): the device's own factors go.
    c.update(&frame(5, 1.0, vec![light("pcf r2", true, 4.0)]), true);
    assert_eq!(c.evaluate_for("pcf", "r2"), c.evaluate);
    let mut cpu = Calibration::default();
    for n in 2..5 {
        cpu.update(
            &frame(
                n,
                1.0,
                vec![light("pcss 7x7-9x9", true, 2.0), light("pcf r2", true, 8.0)],
            ),
            true,
        );
    }
    assert!(near(cpu.evaluate, 5.0), "{cpu:?}");
    assert_eq!(cpu.evaluate_for("pcf", "r2"), cpu.evaluate);
}

/// A frame that measures nothing because the budget priced every light out relaxes every
/// factor toward 1 in log scale, [`CALIBRATION_RELAX`] of the way a frame: measured factors
/// (the global ones and each configuration's) and factors set by hand alike, never past 1,
/// and a measured frame afterwards takes its measurement as before. A frame whose lights
/// measured nothing leaves a factor set by hand as it was.
#[test]
fn a_priced_out_frame_relaxes_every_factor_toward_one() {
    use crate::calibration::CALIBRATION_RELAX;
    let mut c = Calibration::default();
    for _ in 0..3 {
        c.update_gpu(&[
            light("pcf r2", true, 64.0),
            light("pcss 7x7-9x9", true, 1.0 / 4.0),
        ]);
    }
    let (generate, pcf, pcss) = (
        c.generate,
        c.evaluate_for("pcf", "r2"),
        c.evaluate_for("pcss", "7x7-9x9"),
    );
    assert_eq!((pcf, pcss), (64.0, 0.25), "{c:?}");
    let k = 1.0 - CALIBRATION_RELAX;
    let near = |a: f64, b: f64| (a / b - 1.0).abs() < 1e-9;
    for n in 1..=40 {
        c.relax(true);
        let relaxed = |f: f64| f.powf(k.powi(n));
        assert!(near(c.generate, relaxed(generate)), "frame {n}: {c:?}");
        assert!(near(c.evaluate_for("pcf", "r2"), relaxed(pcf)), "frame {n}");
        assert!(
            near(c.evaluate_for("pcss", "7x7-9x9"), relaxed(pcss)),
            "frame {n}"
        );
    }
    assert!(c.evaluate_for("pcf", "r2") > 1.0 && c.evaluate_for("pcss", "7x7-9x9") < 1.0);
    let mut set = Calibration::new(16.0, 4.0, 1.0);
    // A frame whose lights measured nothing keeps a factor set by hand (it was reset to 1).
    let idle = LightStats {
        views_generated: 0,
        receivers_evaluated: 0,
        ..light("pcf r2", false, 1.0)
    };
    set.update_gpu(std::slice::from_ref(&idle));
    set.update(&frame(3, 1.0, vec![idle]), true);
    assert_eq!((set.generate, set.evaluate), (16.0, 4.0));
    set.relax(true);
    assert!(near(set.generate, 16f64.powf(k)) && near(set.evaluate, 4f64.powf(k)));
    assert_eq!(set.core_ms, 1.0);
    // Measured again: the new ratios take the window over as they arrive.
    for _ in 0..CALIBRATION_FRAMES {
        c.update_gpu(&[light("pcf r2", true, 64.0)]);
    }
    assert_eq!(c.evaluate_for("pcf", "r2"), 64.0);
}

/// A priced-out frame whose lamps that keep their maps measured their evaluation relaxes the
/// generation's factor alone: the evaluation's stays as measured (before, relaxing every frame
/// pulled a measured 3 down to about 2.6, underpricing the kept maps).
#[test]
fn a_priced_out_frame_that_measured_evaluations_keeps_their_factor() {
    let mut c = Calibration::default();
    for n in 2..6 {
        c.update(&frame(n, 0.0, vec![light("pcf r2", true, 3.0)]), true);
    }
    assert_eq!((c.generate, c.evaluate), (3.0, 3.0));
    for n in 6..22 {
        // Kept maps: evaluated at 3x, nothing generated.
        c.update(&frame(n, 0.0, vec![light("pcf r2", false, 3.0)]), true);
        c.relax(false);
    }
    assert_eq!(c.evaluate, 3.0, "{c:?}");
    let k = (1.0 - crate::calibration::CALIBRATION_RELAX).powi(16);
    assert!((c.generate / 3f64.powf(k) - 1.0).abs() < 1e-9, "{c:?}");
}
