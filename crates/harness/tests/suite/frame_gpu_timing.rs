//! The GPU frame's device time (`shadow_frame::gpu_timing`): every light's generation and `V`
//! passes timed on the device, read back a frame late without waiting, calibrating the shared
//! budget in device milliseconds; and the budget predicting the texels a GPU frame evaluates.
//! On lavapipe in CI.

use crate::common::{gpu_for_test, texture, upload};
use shadow_frame::gpu_frame::{FrameTextures, VisibilityLayer, record_visibility};
use shadow_frame::{
    Calibration, FrameBackend, FramePipeline, FrameSettings, FrameStats, GpuTiming, LightState,
};
use soft_shadow_core::GpuContext;
use soft_shadow_reference::scenes::lamps::{self, Lamps};
use std::sync::Arc;
use std::time::Instant;

/// The night street's lamps on the GPU backend, `V` into a texture of `gbuffer`'s size (its
/// G-buffer rasterized at that size; the frame's receivers stay at 48 x 27), each lamp in its
/// layer, under a frame budget of `budget_ms`.
pub(crate) struct GpuStreet {
    pub(crate) lamps: Lamps,
    pub(crate) gpu: Arc<GpuContext>,
    positions: wgpu::TextureView,
    normals: wgpu::TextureView,
    visibility: wgpu::Texture,
    pipeline: FramePipeline,
}

impl GpuStreet {
    pub(crate) fn new(gpu: Arc<GpuContext>, (w, h): (u32, u32), budget_ms: f64) -> Self {
        let mut lamps = lamps::build("night-street", 48, 27, budget_ms).unwrap();
        let camera = lamps.camera;
        let (gb, _) = lamps::look(&mut lamps.scene, camera, w, h);
        lamps.look(camera);
        let texels = |f: &dyn Fn(&soft_shadow_core::raster::GBufferTexel) -> [f32; 4]| {
            gb.data().iter().map(f).collect::<Vec<_>>()
        };
        let positions = upload(
            &gpu,
            "positions",
            w,
            h,
            &texels(&|t| {
                let p = t.position;
                [p.x, p.y, p.z, if t.covered { 1.0 } else { 0.0 }]
            }),
        );
        let normals = upload(
            &gpu,
            "normals",
            w,
            h,
            &texels(&|t| [t.normal.x, t.normal.y, t.normal.z, 0.0]),
        );
        let visibility = texture(
            &gpu,
            "visibility",
            (w, h, lamps.lamps.len() as u32),
            wgpu::TextureFormat::R32Float,
            wgpu::TextureUsages::STORAGE_BINDING | wgpu::TextureUsages::COPY_DST,
        );
        let world = &mut lamps.scene.world;
        world.insert_resource(FrameBackend::gpu(gpu.clone()));
        world.insert_resource(FrameSettings::default().with_evaluate_receivers(false));
        for (k, e) in lamps.lamps.iter().enumerate() {
            world.entity_mut(*e).insert(VisibilityLayer(k as u32));
        }
        Self {
            lamps,
            positions: positions.create_view(&Default::default()),
            normals: normals.create_view(&Default::default()),
            visibility,
            gpu,
            pipeline: FramePipeline::new().with_registry(&soft_shadow_techniques::registry()),
        }
    }

    /// One frame, the swinging lamp moved to swing frame `swing`: the pipeline, every lamp's
    /// `V` recorded, submitted, its timestamps and probe asked back (where the world holds a
    /// `GpuTiming`, a `ShadowProbe`) and the device waited for. Returns the statistics and the frame's wall time, milliseconds.
    pub(crate) fn frame(&mut self, swing: u32) -> (FrameStats, f64) {
        let start = Instant::now();
        self.lamps.swing(swing);
        let world = &mut self.lamps.scene.world;
        let stats = self.pipeline.run(world);
        let mut enc = self.gpu.device.create_command_encoder(&Default::default());
        record_visibility(
            world,
            &self.gpu,
            &mut enc,
            &FrameTextures {
                positions: &self.positions,
                normals: &self.normals,
                visibility: &self.visibility,
            },
        )
        .unwrap();
        self.gpu.queue.submit([enc.finish()]);
        shadow_frame::gpu_frame::submitted(world);
        self.gpu.wait().unwrap();
        (stats, start.elapsed().as_secs_f64() * 1e3)
    }
}

/// With a `GpuTiming`, every frame's lamps come back one frame later (the device waited for
/// after each): each lamp with maps has its `V` passes' device time, the swinging lamp its
/// generation's on the frames it made its maps, a lamp without maps none; a frame's device
/// times add up to less than its wall time; no frame goes untimed. The shared budget then
/// calibrates on them: each configuration's evaluation factor lies within its own lamps' last
/// device-over-predicted ratios. Without a `GpuTiming` the same frames calibrate nothing (they
/// time only the recording).
#[test]
#[cfg_attr(
    no_gpu_adapter,
    ignore = "needs a GPU adapter: no Vulkan driver found (apt-get install mesa-vulkan-drivers)"
)]
fn the_gpu_frame_times_its_lights_on_the_device() {
    let Some(ctx) = gpu_for_test("the_gpu_frame_times_its_lights_on_the_device") else {
        return;
    };
    let gpu = Arc::new(ctx);
    if !gpu.has_timestamps() {
        println!("the device has no timestamps: nothing to time");
        return;
    }
    let mut untimed = GpuStreet::new(gpu.clone(), (96, 54), 16.0);
    for f in 0..4 {
        untimed.frame(f);
    }
    let c = untimed.lamps.scene.world.resource::<Calibration>();
    assert_eq!(
        (c.generate, c.evaluate, c.generate_for("pcss", "")),
        (1.0, 1.0, 1.0),
        "a GPU frame without readback calibrates no light"
    );
    let mut street = GpuStreet::new(gpu.clone(), (96, 54), 40.0);
    street
        .lamps
        .scene
        .world
        .insert_resource(GpuTiming::default());
    let swinging = street.lamps.lamps[street.lamps.swinging];
    // Each frame's statistics, wall time and the lamps that had maps.
    let mut last: Option<(FrameStats, f64, Vec<bevy_ecs::entity::Entity>)> = None;
    // Per configuration, its lamps' device-over-predicted `V` times, frame by frame.
    let mut ratios: std::collections::BTreeMap<String, Vec<f64>> = Default::default();
    for f in 0..16u32 {
        let (stats, wall) = street.frame(f);
        let world = &street.lamps.scene.world;
        let timing = world.resource::<GpuTiming>();
        let with_maps: Vec<_> = street
            .lamps
            .lamps
            .iter()
            .copied()
            .filter(|e| world.get::<LightState>(*e).unwrap().maps.is_some())
            .collect();
        if let Some((before, before_wall, had_maps)) = &last {
            if before.frame > 1 {
                for (c, r) in own_ratios(&street, before) {
                    ratios.entry(c).or_default().push(r);
                }
            }
            let times = timing.latest().expect("the last frame's times arrived");
            assert_eq!(times.frame, before.frame, "one frame late");
            let mut device = 0.0;
            for l in &before.lights {
                let t = times.lights.iter().find(|t| t.light == l.light).unwrap();
                let has_maps = had_maps.contains(&l.light);
                let v = t.evaluate_ms.unwrap_or(0.0);
                assert_eq!(
                    t.evaluate_ms.is_some(),
                    has_maps,
                    "frame {}: {} {:?}",
                    before.frame,
                    l.technique,
                    t
                );
                assert!(v >= 0.0 && v.is_finite());
                if l.light == swinging && l.views_generated > 0 {
                    let g = t
                        .generate_ms
                        .expect("the swinging lamp's generation is timed");
                    assert!(g > 0.0, "{t:?}");
                }
                device += v + t.generate_ms.unwrap_or(0.0);
            }
            println!(
                "frame {}: device {device:.2} ms of {before_wall:.2} ms wall, {} lamps with maps",
                before.frame,
                times
                    .lights
                    .iter()
                    .filter(|t| t.evaluate_ms.is_some())
                    .count()
            );
            assert!(device < *before_wall, "{device} ms");
            assert_eq!(device > 0.0, !had_maps.is_empty(), "{device} ms");
        }
        assert_eq!(timing.untimed(), 0);
        last = Some((stats, wall, with_maps));
    }
    // One more frame brings the last one's times.
    let (before, ..) = last.unwrap();
    street.frame(16);
    for (c, r) in own_ratios(&street, &before) {
        ratios.entry(c).or_default().push(r);
    }
    let calibration = street.lamps.scene.world.resource::<Calibration>().clone();
    assert!(
        calibration.evaluate != 1.0,
        "the device times calibrate: {calibration:?}"
    );
    // Each configuration's factor comes from its own lamps' device times: within the range of
    // its last nine ratios, where it has at least three.
    let mut checked = 0;
    for (config, r) in &ratios {
        let last: Vec<f64> = r.iter().rev().take(9).copied().collect();
        if last.len() < 3 {
            continue;
        }
        let (name, variant) = config.split_once(' ').unwrap_or((config, ""));
        let f = calibration.evaluate_for(name, variant);
        let (lo, hi) = last
            .iter()
            .fold((f64::MAX, 0.0f64), |(a, b), &x| (a.min(x), b.max(x)));
        println!("{config}: factor {f:.3}, its last ratios {lo:.3} to {hi:.3}");
        assert!(
            f >= lo * 0.999 && f <= hi * 1.001,
            "{config}: {f} outside {lo}..{hi}"
        );
        checked += 1;
    }
    assert!(checked > 0, "{ratios:?}");
}

/// An `Auto` light on a timed GPU frame holds its budget to its device time: a lamp of the
/// street given `ShadowConfig::auto`, its maps made every frame (caching off), reads as its
/// measured time the device time (generation and `V`) its last timed frame brought, not the
/// wall time of recording its work (which is what it read before: the test fails there).
#[test]
#[cfg_attr(
    no_gpu_adapter,
    ignore = "needs a GPU adapter: no Vulkan driver found (apt-get install mesa-vulkan-drivers)"
)]
fn auto_holds_its_budget_to_the_device_time() {
    let Some(ctx) = gpu_for_test("auto_holds_its_budget_to_the_device_time") else {
        return;
    };
    let gpu = Arc::new(ctx);
    if !gpu.has_timestamps() {
        return;
    }
    let mut street = GpuStreet::new(gpu, (96, 54), 40.0);
    let lamp = street.lamps.lamps[6];
    let world = &mut street.lamps.scene.world;
    world.insert_resource(GpuTiming::default());
    world.insert_resource(
        FrameSettings::default()
            .with_evaluate_receivers(false)
            .with_caching(false),
    );
    let range = world.get::<shadow_frame::ShadowConfig>(lamp).unwrap().range;
    world
        .entity_mut(lamp)
        .insert(shadow_frame::ShadowConfig::auto(50.0).with_range(range));
    let mut checked = 0;
    for _ in 0..7 {
        street.frame(0);
        let world = &street.lamps.scene.world;
        let auto = world
            .get::<shadow_frame::ResolvedTechnique>(lamp)
            .and_then(|r| r.auto);
        let device = world
            .resource::<GpuTiming>()
            .latest()
            .filter(|t| t.frame > 1)
            .and_then(|t| t.lights.iter().find(|l| l.light == lamp))
            .and_then(|l| Some(l.generate_ms? + l.evaluate_ms?));
        // (A pick that stepped down has measured nothing yet.)
        if let (Some(m), Some(d)) = (auto.and_then(|a| a.measured_ms), device) {
            println!("measured {m:.3} ms, device {d:.3} ms");
            assert!((m - d).abs() <= 1e-9 * d.max(1.0), "{m} against {d}");
            checked += 1;
        }
    }
    assert!(checked >= 2, "{checked} frames checked");
}

/// The device time of each lamp's `V` pass over its configuration's predicted evaluation in
/// frame `before`, whose times `street`'s last frame brought, by configuration.
fn own_ratios(street: &GpuStreet, before: &FrameStats) -> Vec<(String, f64)> {
    let world = &street.lamps.scene.world;
    let times = world.resource::<GpuTiming>().latest().unwrap();
    assert_eq!(times.frame, before.frame);
    before
        .lights
        .iter()
        .filter_map(|l| {
            let t = times.lights.iter().find(|t| t.light == l.light)?;
            let ([_, e], v) = (l.profile_ms?, t.evaluate_ms?);
            (e > 0.0 && v > 0.0).then(|| (l.technique.clone(), v / e))
        })
        .collect()
}

/// A GPU frame that records `V` over a renderer's texture runs each light's pass over every
/// texel of it, not over the frame's receivers within the lamp's reach: with the receivers not
/// evaluated, the size `Auto` and the shared budget predict a lamp's evaluation for counts all
/// the texture's texels, each as covered (4 times the receivers, whatever share the lamp's
/// views cover of them); a lamp without casters evaluates nothing; evaluating the receivers,
/// the size counts them. A new texel count shares the budget again at the next frame.
#[test]
fn the_budget_predicts_the_texels_a_gpu_frame_evaluates() {
    use bevy_ecs::system::RunSystemOnce;
    use shadow_frame::RecordedTexels;
    use shadow_frame::scene::LightSource;
    use shadow_frame::tracking::AutoInputs;
    let mut street = lamps::build("night-street", 48, 27, 16.0).unwrap();
    let mut pipeline = FramePipeline::new().with_registry(&soft_shadow_techniques::registry());
    pipeline.run(&mut street.scene.world);
    let receivers = street
        .scene
        .world
        .resource::<shadow_frame::FrameReceivers>()
        .positions
        .len();
    let lights: Vec<_> = street
        .lamps
        .iter()
        .map(|e| {
            let w = &street.scene.world;
            let range = w.get::<shadow_frame::ShadowConfig>(*e).unwrap().range;
            (w.get::<LightSource>(*e).unwrap().0, range)
        })
        .collect();
    let sizes = |world: &mut bevy_ecs::world::World| {
        let lights = lights.clone();
        world
            .run_system_once(move |inputs: AutoInputs| {
                lights
                    .iter()
                    .map(|(l, range)| inputs.size(l, *range))
                    .collect::<Vec<_>>()
            })
            .unwrap()
    };
    let world = &mut street.scene.world;
    let counted = sizes(world);
    world.insert_resource(RecordedTexels(4 * receivers));
    let evaluated = sizes(world);
    world.insert_resource(FrameSettings::default().with_evaluate_receivers(false));
    let texels = sizes(world);
    assert_eq!(
        counted, evaluated,
        "the receivers evaluated are what is predicted"
    );
    let mut partly = 0;
    for (a, b) in counted.iter().zip(&texels) {
        assert_eq!((a.triangles, a.views), (b.triangles, b.views));
        if a.triangles == 0 {
            assert_eq!(a, b);
            continue;
        }
        assert_eq!(
            (b.receivers, b.covered),
            (4 * receivers, 4 * receivers),
            "{a:?}"
        );
        partly += usize::from(a.receivers < receivers);
    }
    assert!(partly > 4, "{partly} lamps reach part of the receivers");
    // Calibrating off, a frame that changes nothing keeps every prediction; one after a new
    // texel count shares the budget again and predicts anew.
    let predicted_v = |stats: &FrameStats| -> Vec<Option<[f64; 2]>> {
        stats.lights.iter().map(|l| l.profile_ms).collect()
    };
    world.insert_resource(
        FrameSettings::default()
            .with_evaluate_receivers(false)
            .with_calibrating(false),
    );
    pipeline.run(world);
    let still = predicted_v(&pipeline.run(world));
    assert_eq!(predicted_v(&pipeline.run(world)), still);
    world.insert_resource(RecordedTexels(40 * receivers));
    let after = predicted_v(&pipeline.run(world));
    assert_ne!(after, still, "shared again on the new texels");
}

/// A budget that prices every lamp out measures nothing, so before it relaxed, the calibration
/// that priced them out held for good. Each such frame now relaxes every factor toward 1
/// (`Calibration::relax`): the night street with 8 ms beyond the pipeline's own work, from a
/// calibration set to 16 times the profile (every lamp's cheapest shadow then over the
/// budget), buys a lamp its shadow again within 64 frames (18 on lavapipe, at a factor of
/// 4.8), and the next frame brings its device time; until then no lamp has maps and the factor
/// falls every frame. (Before, it stayed at 16: the test fails on its first frame.)
#[test]
#[cfg_attr(
    no_gpu_adapter,
    ignore = "needs a GPU adapter: no Vulkan driver found (apt-get install mesa-vulkan-drivers)"
)]
fn a_budget_that_prices_every_lamp_out_measures_the_device_again() {
    let Some(ctx) = gpu_for_test("a_budget_that_prices_every_lamp_out_measures_the_device_again")
    else {
        return;
    };
    let gpu = Arc::new(ctx);
    if !gpu.has_timestamps() {
        println!("the device has no timestamps: nothing to time");
        return;
    }
    const BEYOND_CORE_MS: f64 = 8.0;
    let mut street = GpuStreet::new(gpu, (96, 54), BEYOND_CORE_MS);
    let world = &mut street.lamps.scene.world;
    world.insert_resource(GpuTiming::default());
    world.insert_resource(Calibration::new(16.0, 16.0, 0.0));
    let mut last = 16.0;
    let mut bought = None;
    for f in 0..64u32 {
        let (stats, _) = street.frame(f);
        let world = &mut street.lamps.scene.world;
        let with_maps = street
            .lamps
            .lamps
            .iter()
            .filter(|e| world.get::<LightState>(**e).unwrap().maps.is_some())
            .count();
        let c = world.resource::<Calibration>().clone();
        // The budget beyond the pipeline's own work, whatever this machine takes for that.
        world.insert_resource(shadow_frame::FrameBudget {
            ms: BEYOND_CORE_MS + c.core_ms,
        });
        if with_maps > 0 {
            assert!(f > 0, "a lamp fitted the budget at 16 times the profile");
            bought = Some((f, stats.frame, with_maps, c.generate));
            break;
        }
        assert!(c.generate < last, "frame {f}: {} after {last}", c.generate);
        last = c.generate;
    }
    let (f, frame, n, factor) = bought.expect("no lamp bought a shadow in 64 frames");
    println!("frame {f}: {n} lamps bought a shadow at a generation factor of {factor:.2}");
    street.frame(f + 1);
    let world = &street.lamps.scene.world;
    let times = world
        .resource::<GpuTiming>()
        .latest()
        .expect("times arrived");
    assert_eq!(times.frame, frame);
    assert!(
        times.lights.iter().any(|t| t.evaluate_ms.is_some()),
        "the lamps with a shadow are timed on the device again: {times:?}"
    );
}
