//! What the criterion benches in `generation.rs` and `evaluation.rs` share: the configurations
//! (every technique, variant and baseline the report runs, each on a scene whose light it
//! models), the GPU context, and timing GPU work by its device time.

use criterion::measurement::Measurement;
use criterion::{Bencher, BenchmarkGroup, SamplingMode};
use harness::report::all_techniques;
use harness::scenes::SceneSpec;
use harness::scenes::catalogue::build;
use shadow_core::{DynTechnique, GpuContext, Result, SceneGeometry};
use std::time::{Duration, Instant};

/// Map resolutions of the generation benches.
pub const RESOLUTIONS: [u32; 5] = [128, 256, 512, 1024, 2048];

/// The scene a technique is benched on: `foliage` (3000 quads, rect light) for occlusion-slices,
/// `linear-bar` for linear-light, `torus` (sphere light) for the rest.
pub fn bench_scene(technique: &str) -> &'static str {
    match technique {
        "occlusion-slices" => "foliage",
        "linear-light" => "linear-bar",
        _ => "torus",
    }
}

/// One benched configuration: a technique variant and its scene.
pub struct Config {
    /// The technique.
    pub technique: Box<dyn DynTechnique>,
    /// Its scene.
    pub spec: SceneSpec,
    /// The scene's flattened geometry.
    pub geometry: SceneGeometry,
}

impl Config {
    /// `<technique>-<variant>`.
    pub fn label(&self) -> String {
        format!("{}-{}", self.technique.name(), self.technique.variant())
    }
}

/// Every technique, variant and baseline of the full report, on its bench scene.
pub fn configs() -> Vec<Config> {
    all_techniques(false)
        .into_iter()
        .map(|technique| {
            let spec = build(bench_scene(technique.name())).expect("catalogue scene");
            let geometry = spec.to_scene().expect("scene").geometry();
            Config {
                technique,
                spec,
                geometry,
            }
        })
        .collect()
}

/// The GPU context, or `None` after one line saying why the GPU benches are skipped.
pub fn gpu() -> Option<GpuContext> {
    match GpuContext::new() {
        Ok(g) => {
            eprintln!(
                "GPU benches on {} (device time from timestamp queries: {})",
                g.describe(),
                if g.has_timestamps() { "yes" } else { "no" }
            );
            Some(g)
        }
        Err(e) => {
            eprintln!("GPU benches skipped: {e}");
            None
        }
    }
}

/// Benches `work` by the device time of its passes ([`GpuContext::gpu_time`]); the wall time of
/// an iteration stands in where the device gives no timestamps.
pub fn iter_device_time<T>(b: &mut Bencher, gpu: &GpuContext, mut work: impl FnMut() -> Result<T>) {
    b.iter_custom(|iters| {
        let mut total = Duration::ZERO;
        for _ in 0..iters {
            let start = Instant::now();
            let (out, device) = gpu.gpu_time(&mut work).expect("GPU work");
            total += device.unwrap_or_else(|| start.elapsed());
            drop(out);
        }
        total
    });
}

/// The environment variable that shortens every bench: its value in seconds is each bench's
/// measurement time (a fifth of it the warm-up), with the same number of samples taken flat
/// (each of the same iteration count), so a bench whose iteration outlasts a sample runs about
/// `samples` iterations, not criterion's linear ramp's 55. `benches/device.sh` sets it to fit
/// a lent device's minutes; unset, the benches take the times below.
pub const SECONDS_VAR: &str = "SHADOW_BENCH_SECONDS";

/// Sets `group`'s timing: `samples` samples after 1 s of warm-up over 2 s of measurement, or
/// the times [`SECONDS_VAR`] asks for. One place for every bench group's times.
pub fn timing<M: Measurement>(group: &mut BenchmarkGroup<'_, M>, samples: usize) {
    group.sample_size(samples);
    let quick = std::env::var(SECONDS_VAR)
        .ok()
        .and_then(|s| s.parse::<f64>().ok())
        .filter(|s| s.is_finite() && *s > 0.0);
    match quick {
        Some(s) => group
            .warm_up_time(Duration::from_secs_f64(0.2 * s))
            .measurement_time(Duration::from_secs_f64(s))
            .sampling_mode(SamplingMode::Flat),
        None => group
            .warm_up_time(Duration::from_secs(1))
            .measurement_time(Duration::from_secs(2)),
    };
}
