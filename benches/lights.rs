//! Frame time against the number of lights under one frame budget: `soft_shadow_reference::scenes::lamps::street`'s street
//! with 1, 4, 16 and 64 lamps of five kinds, every lamp a shared choice of a 16 ms
//! `FrameBudget`, 320 x 180 camera receivers. Two frames per light count and backend:
//!
//! - `uncached`: every lamp makes its maps again (the frame the budget is for);
//! - `swing`: one lamp swings, so it alone makes its maps again, and every lamp evaluates.
//!
//! Before timing, twelve frames (the lamp swinging) calibrate the predictions
//! (`shadow_frame::Calibration`); then each count prints how many lamps cast a shadow, how many
//! light nothing the camera sees, and the picks' predicted time against the budget. The timed
//! frames hold that calibration (`FrameSettings::calibrating` off), so they keep the picks and
//! make every map they are to make: no lamp's maps wait a frame (`shadow_frame::deadline`).
//!
//! `cargo bench -p shadow-benches --bench lights [-- <regex>]`; see `benches/README.md`.

use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use harness::animated::pipeline;

use shadow_benches::gpu;
use shadow_frame::{FrameBackend, FrameSettings, LightState};
use soft_shadow_core::GpuContext;
use std::sync::Arc;

/// The frame budget, milliseconds.
const BUDGET_MS: f64 = 16.0;

/// Frames run before timing.
const WARM_UP: u32 = 12;

/// The light counts.
const LIGHTS: [usize; 4] = [1, 4, 16, 64];

fn lights(c: &mut Criterion) {
    let gpu: Option<Arc<GpuContext>> = gpu().map(Arc::new);
    let mut group = c.benchmark_group("frame/night-street");
    group.sample_size(10);
    let mut backends = vec![("cpu", None)];
    if let Some(g) = &gpu {
        backends.push(("gpu", Some(Arc::clone(g))));
    }
    for (backend, g) in backends {
        for n in LIGHTS {
            for caching in [false, true] {
                let mut street =
                    soft_shadow_reference::scenes::lamps::street::street(n, 320, 180, BUDGET_MS)
                        .expect("night street");
                if let Some(g) = &g {
                    street
                        .scene
                        .world
                        .insert_resource(FrameBackend::gpu(Arc::clone(g)));
                }
                street
                    .scene
                    .world
                    .insert_resource(FrameSettings::default().with_caching(caching));
                let mut p = pipeline();
                // The frames the calibration learns from (`shadow_frame::Calibration`), the
                // lamp swinging: the picks timed are those the measured frames settle on.
                let mut first = p.run(&mut street.scene.world);
                for f in 1..=WARM_UP {
                    street.swing(f);
                    first = p.run(&mut street.scene.world);
                }
                if !caching {
                    let idle = street
                        .lamps
                        .iter()
                        .filter(|&&e| {
                            street
                                .scene
                                .world
                                .get::<LightState>(e)
                                .is_some_and(|s| s.share.is_some_and(|s| s.contribution == 0.0))
                        })
                        .count();
                    eprintln!(
                        "{backend} {n} lamps: {} cast a shadow, {idle} light nothing in view; \
                         predicted {:.2} ms of {BUDGET_MS} ms (calibrated; {:.2} kept for the \
                         pipeline); {}",
                        first.lights.len(),
                        first.predicted_ms(),
                        street
                            .scene
                            .world
                            .resource::<shadow_frame::Calibration>()
                            .core_ms,
                        first
                            .lights
                            .iter()
                            .map(|l| format!("{} {}²", l.technique, l.resolution))
                            .collect::<Vec<_>>()
                            .join(", ")
                    );
                }
                // Timed with the calibration held: the same picks, every map made.
                street.scene.world.insert_resource(
                    FrameSettings::default()
                        .with_caching(caching)
                        .with_calibrating(false),
                );
                let id = format!("{backend}/{}", if caching { "swing" } else { "uncached" });
                let mut f = WARM_UP;
                group.bench_with_input(BenchmarkId::new(id, n), &n, |b, _| {
                    b.iter(|| {
                        f += 1;
                        street.swing(f);
                        p.run(&mut street.scene.world)
                    })
                });
            }
        }
    }
    group.finish();
}

criterion_group!(benches, lights);
criterion_main!(benches);
